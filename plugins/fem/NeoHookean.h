#pragma once
// The compressible neo-Hookean material of TLED (Miller, Joldes, Lance and
// Wittek 2007; Taylor, Cheng and Ourselin 2008), in its decoupled form:
//   W(F) = mu / 2 (J^(-2/3) I1 - 3) + kappa / 2 (J - 1)^2,
// J = det F, I1 = tr(F^T F), mu = E / (2 (1 + nu)) the shear modulus and
// kappa = E / (3 (1 - 2 nu)) the bulk modulus. Its first Piola-Kirchhoff
// stress, written with the cofactor cof F = J F^-T so that it has no 1 / J
// in the volumetric part:
//   P = mu J^(-2/3) F + (kappa (J - 1) - mu I1 J^(-5/3) / 3) cof F.
// Units: the FEM's (mm, kg, s), so stresses and moduli in kg / (mm s^2) = kPa
// and forces in kg mm / s^2 = mN.
// These scalar forms are the reference for the vectorised kernel
// (TLEDKernel.cpp) and give the strain energy the tests and reports use.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace trephine::fem {

using Mat3 = Eigen::Matrix3d;

struct ElasticModuli {
  double mu = 0;     // shear modulus, kPa
  double kappa = 0;  // bulk modulus, kPa

  static ElasticModuli fromYoung(double youngModulus, double poissonRatio) {
    return {youngModulus / (2 * (1 + poissonRatio)), youngModulus / (3 * (1 - 2 * poissonRatio))};
  }
  // Lame's first parameter, kPa.
  double lambda() const { return kappa - 2 * mu / 3; }
  // The dilatational (P) wave speed in a material of this density (kg/mm^3), mm/s.
  double dilatationalWaveSpeed(double density) const { return std::sqrt((lambda() + 2 * mu) / density); }
};

inline Mat3 cofactor(const Mat3& F) {
  Mat3 c;
  c << F(1, 1) * F(2, 2) - F(1, 2) * F(2, 1), F(1, 2) * F(2, 0) - F(1, 0) * F(2, 2),
      F(1, 0) * F(2, 1) - F(1, 1) * F(2, 0),  //
      F(0, 2) * F(2, 1) - F(0, 1) * F(2, 2), F(0, 0) * F(2, 2) - F(0, 2) * F(2, 0),
      F(0, 1) * F(2, 0) - F(0, 0) * F(2, 1),  //
      F(0, 1) * F(1, 2) - F(0, 2) * F(1, 1), F(0, 2) * F(1, 0) - F(0, 0) * F(1, 2),
      F(0, 0) * F(1, 1) - F(0, 1) * F(1, 0);
  return c;
}

// Strain energy density, kg / (mm s^2) (times a volume in mm^3: microjoules);
// infinite for J <= 0.
inline double neoHookeanEnergy(const Mat3& F, const ElasticModuli& m) {
  const double J = F.determinant();
  if (!(J > 0)) return INFINITY;
  const double I1 = F.squaredNorm();
  return 0.5 * m.mu * (std::pow(J, -2.0 / 3.0) * I1 - 3) + 0.5 * m.kappa * (J - 1) * (J - 1);
}

// First Piola-Kirchhoff stress, kPa (for J > 0).
inline Mat3 neoHookeanStress(const Mat3& F, const ElasticModuli& m) {
  const double J = F.determinant();
  const double I1 = F.squaredNorm();
  const double Jm23 = std::pow(J, -2.0 / 3.0);
  return m.mu * Jm23 * F + (m.kappa * (J - 1) - m.mu * I1 * Jm23 / (3 * J)) * cofactor(F);
}

// The von Mises equivalent of the Cauchy (true) stress sigma = P F^T / J,
// sqrt(3/2 s:s) with s = sigma - tr(sigma) / 3 I, kPa; J is taken at least
// `minJ` (a squeezed or inverted element has no meaningful true stress).
// Uniaxial stretch F = diag(l, 1, 1) gives mu l^(-5/3) (l^2 - 1).
// Written out as sigma = mu J^(-5/3) dev(F F^T) + kappa (J - 1) I, whose
// deviatoric part is the first term alone (the pressure drops out).
inline double neoHookeanVonMises(const Mat3& F, const ElasticModuli& m, double minJ) {
  const double J = std::max(F.determinant(), minJ);
  const double cubeRoot = std::cbrt(J);
  const Mat3 b = F * F.transpose();
  const Mat3 deviator = b - b.trace() / 3 * Mat3::Identity();
  return std::sqrt(1.5) * m.mu / (J * cubeRoot * cubeRoot) * deviator.norm();
}

}  // namespace trephine::fem
