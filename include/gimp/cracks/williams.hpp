// The crack tip's asymptotic (Williams) fields for unit stress intensity factors: the auxiliary
// fields of the interaction integral that splits J into K_I and K_II.
#pragma once

namespace gimp::cracks {

/// Elastic constants of the tip fields: mu the shear modulus, kappa = 3 - 4 nu (plane strain) or
/// (3 - nu) / (1 + nu) (plane stress).
struct TipElastic {
  double mu = 0, kappa = 0;
};

/// The near-tip field of mode 1 (opening, K_I = 1) or mode 2 (sliding, K_II = 1) at polar
/// position (r, theta) in the tip frame (x1 ahead of the tip along the crack, x2 its normal,
/// -pi < theta <= pi with the faces at +-pi): the stress s = (s11, s22, s12) [Pa per Pa m^0.5]
/// and the displacement's derivative along x1, du1 = (du1/dx1, du2/dx1) [1 per Pa m^0.5].
void williamsField(int mode, double r, double theta, const TipElastic &e, double s[3],
                   double du1[2]);

/// The displacement (u1, u2) of the same field [m per Pa m^0.5].
void williamsDisplacement(int mode, double r, double theta, const TipElastic &e, double u[2]);

} // namespace gimp::cracks
