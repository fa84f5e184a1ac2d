// The scene's material and each body's own (-gimp_material, _E, _nu, _rho; per body
// -gimp_bodyK_material, _E, _nu, _rho; the toughness -gimp_Gc, -gimp_bodyK_Gc), and what the
// stress update derives from them.
#include "scene_options.hpp"

#include <cmath>

namespace gimp::input {

void deriveMaterial(Material &m) {
  m.mu = m.E / (2.0 * (1.0 + m.nu));
  m.lambda = m.E * m.nu / ((1.0 + m.nu) * (1.0 - 2.0 * m.nu));
  m.lambdaStar = m.lambdaEff();
}

namespace {

MaterialModel modelOf(const std::string &name) {
  return name == "neohookean" ? MaterialModel::NeoHookean : MaterialModel::Linear;
}

} // namespace

template <int D> void readMaterial(const Options &o, Scene<D> &sc) {
  Material &m = sc.material;
  bool setE = false, setRho = false;
  m.model = modelOf(o.choice("gimp_material", "linear"));
  m.E = o.real("gimp_E", m.E, &setE);
  m.nu = o.real("gimp_nu", m.nu);
  m.rho = o.real("gimp_rho", m.rho, &setRho);
  if constexpr (D == 2) {
    m.planeStrain = o.choice("gimp_plane", "strain") == "strain";
    m.thickness = o.real("gimp_thickness", m.thickness);
  }
  m.Gc = o.real("gimp_Gc", m.Gc);
  // E and rho may be left to the bodies (-gimp_bodyK_E, _rho): a body that has neither its own
  // nor the scene's is refused in readBodyMaterial.
  sc.sceneE = setE;
  sc.sceneRho = setRho;
  deriveMaterial(m);
}

void readBodyMaterial(const Options &o, const std::string &p, const Material &scene, bool sceneE,
                      bool sceneRho, Material &m) {
  m = scene;
  const std::string model = m.model == MaterialModel::Linear ? "linear" : "neohookean";
  bool setE = false, setRho = false;
  m.model = modelOf(o.choice(p + "material", model));
  m.E = o.real(p + "E", m.E, &setE);
  m.nu = o.real(p + "nu", m.nu);
  m.rho = o.real(p + "rho", m.rho, &setRho);
  m.Gc = o.real(p + "Gc", m.Gc);
  if (o.help()) return;
  if (!setE && !sceneE)
    Options::bad(p + "E", "(missing)",
                 "the body has no Young's modulus: give it -" + p +
                     "E or the scene's -gimp_E [Pa]");
  if (!setRho && !sceneRho)
    Options::bad(p + "rho", "(missing)",
                 "the body has no density: give it -" + p +
                     "rho or the scene's -gimp_rho "
                     "[kg/m^3]");
  deriveMaterial(m);
}

template void readMaterial<2>(const Options &, Scene<2> &);
template void readMaterial<3>(const Options &, Scene<3> &);

} // namespace gimp::input
