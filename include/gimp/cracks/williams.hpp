// The crack tip's asymptotic (Williams) fields for unit stress intensity factors: the auxiliary
// fields of the interaction integral that splits J into K_I and K_II (in 2D), and into K_I, K_II
// and K_III along a 3D crack front.
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

/// The 3D auxiliary field of a crack front for a unit K of mode 1 (opening), 2 (sliding) or 3
/// (tearing), in the front's local right-handed frame: x1 ahead (in the crack's plane, into the
/// material), x2 the crack's normal, x3 = x1 x x2 along the front; (r, theta) polar in the
/// (x1, x2) plane as in williamsField. Modes 1 and 2 are the plane-strain Williams fields (e.kappa
/// must be 3 - 4 nu) with s33 = nu (s11 + s22) and no displacement along x3; mode 3 is antiplane
/// shear, s13 = -sin(theta / 2) / sqrt(2 pi r), s23 = cos(theta / 2) / sqrt(2 pi r) and
/// u3 = (2 / mu) sqrt(r / 2 pi) sin(theta / 2). s is the stress [Pa per Pa m^0.5], g[i][j] =
/// du_i/dx_j [1 per Pa m^0.5] (zero along x3: the field does not vary along the front).
void frontField(int mode, double r, double theta, const TipElastic &e, double s[3][3],
                double g[3][3]);

/// frontField of the three modes at one point: s[m - 1], g[m - 1] for mode m (the trigonometric
/// values of theta found once for all three).
void frontFields(double r, double theta, const TipElastic &e, double s[3][3][3], double g[3][3][3]);

/// The displacement (u1, u2, u3) of the same field [m per Pa m^0.5].
void frontDisplacement(int mode, double r, double theta, const TipElastic &e, double u[3]);

} // namespace gimp::cracks
