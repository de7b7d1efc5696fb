#pragma once
// The trajectory family psi = (theta, l, gamma) of eqs 3.37-3.40 on a grid (thesis 3.5, 3.7), and
// each trajectory's cost from the arm's inverse dynamics: energy (eq 3.41) and precision
// (eqs 3.42-3.43, SPEC section 2's reading). Computed once per arm model and grid and cached in a
// versioned file, so that planning only interpolates.
//
// Every trajectory starts at rest at `start` (world frame, m), lasts `duration` seconds
// (robot::psi_trajectory: shaped quadratic Bezier), and ends at rest at
// p2 = start + l (sin theta, cos theta, 0).

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "proprio/planning/arm_motion.hpp"
#include "proprio/robot/arm.hpp"
#include "proprio/robot/trajectory.hpp"

namespace proprio::planning {

/// `count` evenly spaced values from `min` to `max` (count 1: min).
struct GridAxis {
  double min = 0;
  double max = 0;
  int count = 1;
  [[nodiscard]] double value(int i) const;
};

/// The thesis's grid (3.7): 6 x 7 x 6 = 252 trajectories over theta in [-1.5, 1.5] rad,
/// l in [0.07, 0.21] m, gamma in [-0.3, 0.3] (the thesis prints 3: a typo, SPEC section 2).
struct GridSpec {
  /// p0: the arm's rest point before a move, world frame, m. The default lies in front of the arm
  /// and to its right so that every end point of the grid is reachable
  /// (docs/results/interception.md).
  Eigen::Vector3d start{0.25, -0.15, 0.05};
  double duration = 1.0;  ///< of every move, s
  GridAxis theta{-1.5, 1.5, 6};
  GridAxis length{0.07, 0.21, 7};
  GridAxis gamma{-0.3, 0.3, 6};

  [[nodiscard]] int size() const { return theta.count * length.count * gamma.count; }
  /// Index of grid point (i_theta, i_length, i_gamma); gamma varies fastest.
  [[nodiscard]] int index(int i_theta, int i_length, int i_gamma) const {
    return (i_theta * length.count + i_length) * gamma.count + i_gamma;
  }
  [[nodiscard]] robot::TrajectoryParams params(int index) const;
  /// The end point p2 of psi (eq 3.39, relative to the start).
  [[nodiscard]] Eigen::Vector3d end_point(const robot::TrajectoryParams& psi) const;
  /// The trajectory of psi (robot::psi_trajectory).
  [[nodiscard]] robot::BezierTrajectory trajectory(const robot::TrajectoryParams& psi) const;
  /// Throws Error when a value is out of range (counts >= 1, min <= max, l > 0, duration > 0).
  void validate() const;
};

struct GridCostOptions {
  GridSpec grid;
  ArmMotionOptions motion;
  /// Sampling rate of the joint trajectories and torques, Hz.
  double rate_hz = 100;
  /// Perturbed end points per trajectory for the precision (eq 3.42).
  int precision_samples = 500;
  /// Std of the Gaussian perturbation of the end point, per axis, m.
  double perturbation_std = 0.005;
  /// eps of rho_k = integral |mean_k| / (std_k + eps) dt, N m: the torque std is 0 at t = 0.
  double snr_eps = 0.01;
  /// Seed of the perturbations (each grid point draws from its own stream, so the result does
  /// not depend on the number of threads).
  std::uint64_t seed = 1;
  /// Worker threads; 0 = the hardware's.
  int threads = 0;
  /// Throws Error when an option is out of range.
  void validate() const;
};

/// The costs of one trajectory of the grid.
struct GridPoint {
  robot::TrajectoryParams psi;
  bool valid = false;
  std::string why_invalid;  ///< the tracking error, when !valid
  robot::JointVector energy_per_joint = robot::JointVector::Zero();  ///< E_k, N m s (eq 3.41)
  double energy = 0;                                                 ///< sum over joints
  robot::JointVector rho_per_joint = robot::JointVector::Zero();     ///< rho_k, s (eq 3.42)
  double rho = 0;                                                    ///< sum over joints
  int samples_used = 0;  ///< perturbed end points that were reachable
};

struct GridCostsSummary {
  int valid = 0;
  int invalid = 0;
  double seconds = 0;     ///< compute time (0 when read from the cache)
  std::string source;     ///< "computed", "cache", or "computed (cache ...)" with the reason
  double median_rho = 0;  ///< over valid points
};

struct GridCosts {
  GridCostOptions options;
  std::string key;  ///< grid_cache_key of the arm and options
  std::vector<GridPoint> points;
  /// c of eq 3.43, Sigma_psi = c / rho I (m^2 s): the median trajectory gets perturbation_std^2.
  double sigma_scale = 0;
  GridCostsSummary summary;
};

/// A hash (hex) of everything the costs depend on: the compiled arm model (its MJB bytes), the
/// arm's part names, every option except `threads`, and the cache format version.
std::string grid_cache_key(const robot::Arm& arm, const GridCostOptions& options);

/// Energy and precision of every grid trajectory, from the arm at rest at the grid's start (its
/// scheduled-pitch IK solution). A trajectory that cannot be tracked is marked invalid with the
/// reason; a perturbed end point that cannot be reached is left out of that point's statistics
/// (a point needs half of them). Throws Error when the start point itself is unreachable.
/// `show_progress` draws a progress bar on stderr.
GridCosts compute_grid_costs(const robot::Arm& arm, const GridCostOptions& options,
                             bool show_progress = false);

/// 2: the precision samples drawn from core::stream_seed streams (1: an earlier seed scheme).
inline constexpr int kGridCacheVersion = 2;

/// Writes the costs as JSON (format "proprio.intercept.grid_costs", version kGridCacheVersion),
/// atomically.
void write_grid_costs(const std::filesystem::path& path, const GridCosts& costs);
/// Reads them back (the options are restored except `threads`). Throws Error naming the file for
/// a syntax error, another format or version, a missing or mistyped field, a point count that
/// does not match the grid, or non-finite numbers.
GridCosts read_grid_costs(const std::filesystem::path& path);

/// The costs from `cache` when it holds the same key; otherwise computes them and rewrites the
/// cache (a stale or unreadable cache is replaced, and the summary's source says why).
GridCosts load_or_compute_grid_costs(const robot::Arm& arm, const GridCostOptions& options,
                                     const std::filesystem::path& cache,
                                     bool show_progress = false);

/// The costs as smooth functions of psi for the planner: tensor Catmull-Rom interpolation of
/// log E and log rho over the grid, psi clamped to the grid's box. Invalid points take the worst
/// valid value times e (log E + 1, log rho - 1), so the planner avoids them.
class GridCostModel {
 public:
  /// Throws Error when no grid point is valid.
  explicit GridCostModel(GridCosts costs);

  [[nodiscard]] const GridCosts& costs() const { return costs_; }
  [[nodiscard]] const GridSpec& grid() const { return costs_.options.grid; }

  /// log of the total energy, log(N m s), at psi = (theta, l, gamma).
  [[nodiscard]] double log_energy(const Eigen::Vector3d& psi) const;
  /// log of the summed precision rho, log(s).
  [[nodiscard]] double log_rho(const Eigen::Vector3d& psi) const;
  /// The arm's end-point variance per axis, sigma_scale / rho (eq 3.43), m^2.
  [[nodiscard]] double arm_variance(const Eigen::Vector3d& psi) const;
  /// psi clamped to the grid's box.
  [[nodiscard]] Eigen::Vector3d clamp(const Eigen::Vector3d& psi) const;

 private:
  [[nodiscard]] double interpolate(const std::vector<double>& values,
                                   const Eigen::Vector3d& psi) const;
  GridCosts costs_;
  std::vector<double> log_energy_;
  std::vector<double> log_rho_;
};

}  // namespace proprio::planning
