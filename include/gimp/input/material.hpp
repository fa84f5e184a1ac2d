// A body's material as the scene gives it (E, nu, rho, the model) and what the stress update
// derives from it.
#pragma once

namespace gimp {

enum class MaterialModel { Linear, NeoHookean };

struct Material {
  MaterialModel model = MaterialModel::Linear;
  double E = 0, nu = 0, rho = 0;
  bool planeStrain = true; // 2D: plane strain, else plane stress (3D: always the 3D model)
  double thickness = 1.0;  // 2D: the out-of-plane thickness [m] (3D: 1)
  double Gc = 0;           // 2D: the toughness, the G at which a crack tip grows [J/m^2] (0: none)
  // derived
  double lambda = 0, mu = 0;
  double lambdaStar = 0;    // lambdaEff(), stored for the stress update
  double lambdaEff() const; // lambda, or its plane-stress reduction
  double waveSpeed() const; // P-wave speed of the model [m/s]
};

} // namespace gimp
