// The auxiliary fields of a 3D crack front in global axes, and the curvature terms they bring to
// the interaction integrals where they turn with a curved front (include/gimp/cracks/front.hpp).
//
// A front frame: e1 = a (ahead, in the crack's plane), e2 = n (the crack's normal), e3 = a x n;
// a point at local (x1, x2) in it. The fields are the straight front's (frontField,
// include/gimp/cracks/williams.hpp): the plane-strain tip fields of unit K_I, K_II and the
// antiplane field of unit K_III.
#pragma once

#include "gimp/core/tensor.hpp"
#include "gimp/cracks/williams.hpp"

#include <array>

namespace gimp::cracks {

/// The auxiliary fields of unit modes 1, 2, 3 (S[m - 1], G[m - 1]) at local (x1, x2) of the
/// frame (e1, e2, e3) in global axes: S the stress [Pa per Pa m^0.5], G the displacement gradient
/// [per Pa m^0.5].
void frontAuxGlobal(const TipElastic &el, double x1, double x2, const std::array<double, 3> &e1,
                    const std::array<double, 3> &e2, const std::array<double, 3> &e3,
                    double S[3][3][3], double G[3][3][3]);

/// The curvature terms' integrand of the three interaction integrals at a point: t[m - 1] =
/// e1_k dP^m_kj/dx_j, with P^m_kj = sigma_ij G_ik + S_ij H_ik - S_ij eps_ij delta_kj (S, G the
/// unit mode m field, sigma, H = grad u the particle's). Where the fields' frame turns with the
/// front, S is not in equilibrium and G is not a gradient; with the particle's field in
/// equilibrium and compatible, dP^m_kj/dx_j = dS_ij/dx_j H_ik + sigma_ij (dG_ik/dx_j -
/// dG_ij/dx_k), zero on a straight front. The derivatives are those of the fields carried by a
/// smooth front through the frame's origin: x1 and x2 change along e1 and e2, and the frame turns
/// with the arc length s, de1/ds = c (the curvature vector, in the crack's plane), de2/ds = 0,
/// de3/ds = c x e2, ds/dx = t / (1 + kappa x1), kappa = c . t; curv = c t^T (t the front's unit
/// tangent). The tip fields' own derivatives along x1 and x2 are fourth-order central differences
/// with steps of 1e-3 r (behind the front at most a quarter of |x2|, so that they stay on the
/// point's side of the crack's plane). Returns false, with t untouched, on the front or on the
/// crack's plane behind it, and beyond the front's centre of curvature (1 + kappa x1 <= 0),
/// where the smooth front's frame is not defined.
bool curvatureIntegrand(const TipElastic &el, double x1, double x2,
                        const std::array<double, 3> e[3], const double curv[3][3],
                        const Tensor<3> &sigma, const Tensor<3> &H, double t[3]);

} // namespace gimp::cracks
