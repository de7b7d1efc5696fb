#pragma once
// Visual uncertainty of a stereo pair (thesis 3.4.2, eqs 3.18-3.21; SPEC §1-2): how Gaussian pixel
// noise in the two cameras spreads into the triangulated world point.

#include <Eigen/Core>

#include "proprio/geometry/camera.hpp"

namespace proprio::geometry {

/// log p(X | x1, x2) up to an additive constant (eqs 3.20-3.21, uniform prior on X):
/// sum over i of log N(x_i | pi(P_i X), Sigma), with the Gaussians' normalisation included, so the
/// value is the log of the likelihood product; the missing constant is -log p(x1, x2).
/// x_i are ideal pixels; Sigma (2x2, pixels^2) must be symmetric positive definite.
double log_posterior(const Matrix34d& P1, const Matrix34d& P2, const Eigen::Vector2d& x1,
                     const Eigen::Vector2d& x2, const Eigen::Vector3d& X,
                     const Eigen::Matrix2d& Sigma);

/// Linearised covariance of the triangulated point at X (world units^2):
/// Cov = (J1^T Sigma^-1 J1 + J2^T Sigma^-1 J2)^-1 with J_i = projection_jacobian(P_i, X), the
/// Laplace approximation of p(X | x1, x2) at its mode. It equals G Sigma_4 G^T for the Jacobian G
/// of the maximum-likelihood triangulation with respect to the four pixel coordinates (SPEC §2's "J
/// Sigma J^T"). Throws Error when X lies on the baseline (depth along it is unobservable) or behind
/// a camera.
Eigen::Matrix3d triangulation_covariance(const Matrix34d& P1, const Matrix34d& P2,
                                         const Eigen::Vector3d& X, const Eigen::Matrix2d& Sigma);

}  // namespace proprio::geometry
