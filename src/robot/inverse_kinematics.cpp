#include "proprio/robot/inverse_kinematics.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <vector>

#include "proprio/core/error.hpp"
#include "text.hpp"

namespace proprio::robot {
namespace {

using detail::cat;
using detail::num;
constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2 * std::numbers::pi;
/// Samples per side of the reachable pitch window when the nearest pitch breaks a joint limit.
constexpr int kPitchScan = 90;
/// Pitches closer than this count as equal when choosing among solutions, rad.
constexpr double kPitchTie = 1e-9;

double wrap(double a) { return std::remainder(a, kTwoPi); }

std::string point(const Eigen::Vector3d& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.4f, %.4f, %.4f) m", p.x(), p.y(), p.z());
  return buf;
}

Error ik_error(const Eigen::Vector3d& target, const std::string& why) {
  std::string message = "IK target ";
  message += point(target);
  message += " ";
  message += why;
  return Error(message);
}

/// The representative of angle `a` (mod 2 pi) inside [lo, hi] nearest to `hint`, if any.
std::optional<double> in_range(double a, double lo, double hi, double hint) {
  std::optional<double> best;
  for (int k = -2; k <= 2; ++k) {
    double v = a + kTwoPi * k;
    if (v < lo - 1e-9 || v > hi + 1e-9) continue;
    v = std::clamp(v, lo, hi);
    if (!best || std::abs(v - hint) < std::abs(*best - hint)) best = v;
  }
  return best;
}

/// Appendix A in the arm's vertical plane: the wrist point from the approach angle (A.18), the
/// elbow on the circle of A.14-A.15 at t = pi (elbow up) or t = 0, then the three pitch-joint
/// rotations ("raising" angles, positive up) relative to the zero configuration.
std::optional<std::array<double, 3>> planar_solve(const ArmGeometry& g, double u, double z,
                                                  double pitch, bool elbow_up) {
  const Eigen::Vector2d v = Eigen::Vector2d(u, z) - g.shoulder -
                            g.hand * Eigen::Vector2d(std::cos(pitch), std::sin(pitch));
  const double vn = v.norm();
  if (vn < 1e-12) return std::nullopt;
  const double a2 = g.upper_arm * g.upper_arm;
  const double ab = 0.5 * (vn * vn - a2 - g.forearm * g.forearm);  // A.8
  const double c = (a2 + ab) / vn;                                 // A.9: a . n = c
  const double rho2 = a2 - c * c;                                  // A.14: circle radius^2
  if (rho2 < -1e-12 * a2) return std::nullopt;
  const double rho = std::sqrt(std::max(0.0, rho2));
  const Eigen::Vector2d n = v / vn;
  const Eigen::Vector2d n_down(n.y(), -n.x());  // in-plane normal below the shoulder-wrist line
  const double t = elbow_up ? kPi : 0.0;
  const Eigen::Vector2d a = c * n + rho * std::cos(t) * n_down;  // A.15 with sin t = 0 (A.19)
  const Eigen::Vector2d b = v - a;
  const double elev_a = std::atan2(a.y(), a.x());
  const double elev_b = std::atan2(b.y(), b.x());
  return std::array<double, 3>{wrap(elev_a - g.link_zero[0]),
                               wrap(elev_b - elev_a - (g.link_zero[1] - g.link_zero[0])),
                               wrap(pitch - elev_b - (g.link_zero[2] - g.link_zero[1]))};
}

struct Candidate {
  JointVector q;
  double pitch_gap;  // |pitch - requested|
  bool elbow_up;
  double distance;  // to q_start
};

/// Choice among solutions: nearest pitch, then the preferred elbow, then nearest to the start.
bool better(const Candidate& c, const Candidate& best, bool elbow_up) {
  if (c.pitch_gap < best.pitch_gap - kPitchTie) return true;
  if (c.pitch_gap > best.pitch_gap + kPitchTie) return false;
  if (c.elbow_up != best.elbow_up) return c.elbow_up == elbow_up;
  return c.distance < best.distance;
}

void check_target(const Arm& arm, const Eigen::Vector3d& target, const IkOptions& options) {
  if (!target.allFinite()) throw ik_error(target, "is not finite");
  if (target.z() < options.min_height) {
    throw ik_error(target, cat({"is below the table (z < ", num(options.min_height), " m)"}));
  }
  const ArmGeometry& g = arm.geometry();
  const double radial = (target.head<2>() - g.base_xy).norm();
  if (g.base_radius > 0 && radial < g.base_radius + options.base_clearance &&
      target.z() < g.base_top + options.base_clearance) {
    throw ik_error(target, cat({"is inside the arm's base (within ", num(g.base_radius),
                                " m of the yaw axis and below ", num(g.base_top), " m)"}));
  }
  if (g.analytic) {
    const double forward =
        Eigen::Vector2d(radial - g.shoulder.x(), target.z() - g.shoulder.y()).norm();
    const double back =
        Eigen::Vector2d(-radial - g.shoulder.x(), target.z() - g.shoulder.y()).norm();
    const double dist = std::min(forward, back);
    if (dist > g.reach * (1 + 1e-12)) {
      throw ik_error(target, cat({"is out of reach (", num(dist), " m from the shoulder, reach ",
                                  num(g.reach), " m)"}));
    }
  }
}

IkResult finish(ArmState& state, const Eigen::Vector3d& target, const JointVector& q,
                const IkOptions& options, IkSummary summary) {
  IkResult result;
  result.q = q;
  const EePose pose = state.ee_pose(q);
  result.pitch = pose.pitch();
  summary.residual = (pose.position - target).norm();
  summary.pitch_met = std::abs(wrap(result.pitch - options.pitch)) < 1e-9;
  result.summary = std::move(summary);
  return result;
}

IkResult solve_analytic(ArmState& state, const Eigen::Vector3d& target, const JointVector& q_start,
                        const IkOptions& options) {
  const Arm& arm = state.arm();
  const ArmGeometry& g = arm.geometry();
  if (!g.analytic) {
    throw Error::in_file(arm.source(),
                         cat({"the arm has no analytic inverse kinematics: ", g.why_not_analytic}));
  }
  const Eigen::Vector2d rel = target.head<2>() - g.base_xy;
  const double radial = rel.norm();
  // On the yaw axis any azimuth works: keep the current one.
  const double azimuth =
      radial > 1e-12 ? std::atan2(rel.y(), rel.x()) : g.yaw_zero + g.yaw_sign * q_start[0];
  struct Branch {
    double azimuth;
    double u;
    PitchWindow window;
  };
  std::vector<Branch> branches;
  for (const double side : {1.0, -1.0}) {
    const double u = side * radial;
    branches.push_back({azimuth + (side > 0 ? 0.0 : kPi), u, reachable_pitch(g, u, target.z())});
  }

  // (branch, pitch) pairs ordered by how far the pitch is from the requested one.
  struct Try {
    std::size_t branch;
    double pitch;
    double gap;
  };
  // First the requested pitch (or the nearest reachable one) on each branch; only when joint
  // limits rule those out, a scan over each branch's reachable pitches.
  auto make_tries = [&](bool scan) {
    std::vector<Try> tries;
    for (std::size_t b = 0; b < branches.size(); ++b) {
      const PitchWindow& w = branches[b].window;
      if (w.empty()) continue;
      const double delta = wrap(options.pitch - w.phi);
      auto add = [&](double d) {
        const double p = wrap(w.phi + d);
        tries.push_back({b, p, std::abs(wrap(p - options.pitch))});
      };
      const double ad = std::abs(delta);
      if (ad >= w.lo - 1e-12 && ad <= w.hi + 1e-12) {
        add(delta);  // the requested pitch itself
      } else if (!options.strict_pitch) {
        const double clamped = std::clamp(ad, w.lo, w.hi);
        add(delta >= 0 ? clamped : -clamped);
        if (delta == 0) add(-clamped);
      }
      if (scan && !options.strict_pitch) {
        for (const double sign : {1.0, -1.0}) {
          for (int i = 0; i <= kPitchScan; ++i) add(sign * (w.lo + (w.hi - w.lo) * i / kPitchScan));
        }
      }
    }
    std::stable_sort(tries.begin(), tries.end(),
                     [](const Try& a, const Try& b) { return a.gap < b.gap; });
    return tries;
  };
  // The best valid solution among `tries`; `failed_gap` is the smallest pitch gap that failed.
  auto choose = [&](const std::vector<Try>& tries, double& failed_gap) {
    std::optional<Candidate> best;
    failed_gap = std::numeric_limits<double>::infinity();
    for (const Try& t : tries) {
      if (best && t.gap > best->pitch_gap + kPitchTie) break;
      bool found = false;
      const Branch& br = branches[t.branch];
      const std::optional<double> q1 = in_range(g.yaw_sign * wrap(br.azimuth - g.yaw_zero),
                                                arm.lower()[0], arm.upper()[0], q_start[0]);
      for (const bool up : {options.elbow_up, !options.elbow_up}) {
        if (!q1 || (up != options.elbow_up && !options.allow_elbow_flip)) continue;
        const auto raise = planar_solve(g, br.u, target.z(), t.pitch, up);
        if (!raise) continue;
        JointVector q;
        q[0] = *q1;
        bool ok = true;
        for (int k = 0; k < 3 && ok; ++k) {
          const auto qk = in_range(
              g.pitch_sign[static_cast<std::size_t>(k)] * (*raise)[static_cast<std::size_t>(k)],
              arm.lower()[k + 1], arm.upper()[k + 1], q_start[k + 1]);
          ok = qk.has_value();
          if (ok) q[k + 1] = *qk;
        }
        if (!ok) continue;
        q[4] = std::clamp(q_start[4], arm.lower()[4], arm.upper()[4]);
        const Candidate c{q, t.gap, up, (q - q_start).norm()};
        if (!best || better(c, *best, options.elbow_up)) best = c;
        found = true;
      }
      if (!found) failed_gap = std::min(failed_gap, t.gap);
    }
    return best;
  };
  double failed_gap = 0;
  std::optional<Candidate> best = choose(make_tries(false), failed_gap);
  if (!options.strict_pitch && (!best || failed_gap < best->pitch_gap - kPitchTie)) {
    best = choose(make_tries(true), failed_gap);
  }
  if (!best) {
    bool any_window = false;
    for (const Branch& br : branches) any_window = any_window || !br.window.empty();
    if (!any_window) {
      throw ik_error(target, "is out of reach (no wrist position puts the ee there)");
    }
    if (options.strict_pitch) {
      throw ik_error(target, cat({"has no solution with pitch ", num(options.pitch),
                                  " rad within the joint limits"}));
    }
    throw ik_error(target, "has no solution within the joint limits");
  }
  IkSummary summary;
  summary.method = IkMethod::analytic;
  summary.elbow_up = best->elbow_up;
  summary.message = best->pitch_gap < kPitchTie
                        ? "analytic solution at the requested pitch"
                        : "analytic solution at the nearest reachable pitch";
  IkResult result = finish(state, target, best->q, options, std::move(summary));
  if (result.summary.residual > 1e-7) {
    // The geometry read from the model does not describe its kinematics: a bug, not bad input.
    throw std::logic_error(cat({"analytic IK disagrees with MuJoCo's forward kinematics by ",
                                num(result.summary.residual), " m"}));
  }
  return result;
}

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

IkResult solve_numerical(ArmState& state, const Eigen::Vector3d& target, const JointVector& q_start,
                         const IkOptions& options) {
  const Arm& arm = state.arm();
  const ArmGeometry& g = arm.geometry();
  JointVector q = arm.clamp(q_start);
  // Requested pointing direction: in the vertical plane through the yaw axis and the target.
  Eigen::Vector2d rel = target.head<2>() - g.base_xy;
  if (rel.norm() < 1e-9) {
    const double az = g.yaw_zero + g.yaw_sign * q[0];
    rel = Eigen::Vector2d(std::cos(az), std::sin(az));
  }
  rel.normalize();
  const Eigen::Vector3d wanted(std::cos(options.pitch) * rel.x(), std::cos(options.pitch) * rel.y(),
                               std::sin(options.pitch));

  bool use_direction = true;
  double lambda = options.initial_damping;
  int iterations = 0;
  int budget = options.max_iterations;
  int stalls = 0;
  std::vector<mjtNum> jp(3 * static_cast<std::size_t>(arm.model().nv));
  std::vector<mjtNum> jr(jp.size());
  auto evaluate = [&](const JointVector& qq, Eigen::VectorXd& e, Eigen::MatrixXd* J) {
    const EePose pose = state.ee_pose(qq);
    const int rows = use_direction ? 6 : 3;
    e.resize(rows);
    e.head<3>() = target - pose.position;
    const Eigen::Vector3d d = pose.rotation.col(0);
    if (use_direction) e.tail<3>() = options.pitch_weight * (wanted - d);
    if (J) {
      J->resize(rows, kArmJoints);
      mj_jacSite(&arm.model(), &state.data(), jp.data(), jr.data(), arm.ee_site());
      Eigen::Matrix<double, 3, kArmJoints> Jp;
      Eigen::Matrix<double, 3, kArmJoints> Jr;
      for (int r = 0; r < 3; ++r) {
        for (int k = 0; k < kArmJoints; ++k) {
          const std::size_t i =
              static_cast<std::size_t>(r) * static_cast<std::size_t>(arm.model().nv) +
              static_cast<std::size_t>(arm.dof_adr(k));
          Jp(r, k) = jp[i];
          Jr(r, k) = jr[i];
        }
      }
      J->topRows<3>() = Jp;
      // d(d)/dt = omega x d = -[d]x omega.
      if (use_direction) J->bottomRows<3>() = -options.pitch_weight * skew(d) * Jr;
    }
  };
  auto converged = [&](const Eigen::VectorXd& e) {
    if (e.head<3>().norm() >= options.tolerance) return false;
    return !use_direction || e.tail<3>().norm() < 1e-9 * options.pitch_weight;
  };

  Eigen::VectorXd e, e_new;
  Eigen::MatrixXd J, J_new;
  evaluate(q, e, &J);
  std::string how;
  while (true) {
    if (converged(e)) {
      how = use_direction ? "converged at the requested pitch" : "converged (pitch not reachable)";
      break;
    }
    if (iterations >= budget || stalls >= 8 || lambda > 1e8) {
      if (use_direction && !options.strict_pitch) {
        // Position first: the requested pitch is not reachable from here, drop it and give the
        // position-only phase its own budget.
        use_direction = false;
        lambda = options.initial_damping;
        stalls = 0;
        budget = iterations + options.max_iterations;
        evaluate(q, e, &J);
        continue;
      }
      char buf[160];
      std::snprintf(buf, sizeof buf,
                    "was not reached by the numerical IK: closest %.3g m after %d iterations",
                    e.head<3>().norm(), iterations);
      throw ik_error(target, buf);
    }
    ++iterations;
    // Damped least squares step (J^T J + lambda^2 I) dq = J^T e; joints at a limit that the step
    // would push further out are frozen and the step recomputed.
    Eigen::Matrix<double, kArmJoints, 1> free = Eigen::Matrix<double, kArmJoints, 1>::Ones();
    JointVector dq;
    for (int pass = 0; pass < 2; ++pass) {
      const Eigen::MatrixXd Jf = J * free.asDiagonal();
      Eigen::Matrix<double, kArmJoints, kArmJoints> A = Jf.transpose() * Jf;
      A.diagonal().array() += lambda * lambda;
      dq = A.ldlt().solve(Jf.transpose() * e);
      bool changed = false;
      for (int k = 0; k < kArmJoints; ++k) {
        const bool at_low = q[k] <= arm.lower()[k] + 1e-12 && dq[k] < 0;
        const bool at_high = q[k] >= arm.upper()[k] - 1e-12 && dq[k] > 0;
        if (free[k] > 0 && (at_low || at_high)) {
          free[k] = 0;
          changed = true;
        }
      }
      if (!changed) break;
    }
    const JointVector q_new = arm.clamp(q + dq);
    evaluate(q_new, e_new, &J_new);
    if (e_new.squaredNorm() < e.squaredNorm()) {
      const double gain = e.squaredNorm() - e_new.squaredNorm();
      stalls = gain < 1e-15 * e.squaredNorm() ? stalls + 1 : 0;
      q = q_new;
      e.swap(e_new);
      J.swap(J_new);
      lambda = std::max(lambda / 4, 1e-9);
    } else {
      lambda *= 8;
      ++stalls;
    }
  }
  IkSummary summary;
  summary.method = IkMethod::numerical;
  summary.iterations = iterations;
  summary.message = how;
  return finish(state, target, q, options, std::move(summary));
}

}  // namespace

const char* to_string(IkMethod method) {
  switch (method) {
    case IkMethod::automatic:
      return "automatic";
    case IkMethod::analytic:
      return "analytic";
    case IkMethod::numerical:
      return "numerical";
  }
  return "?";
}

void IkOptions::validate() const {
  require(std::isfinite(pitch), "IkOptions: pitch must be finite");
  require(std::isfinite(min_height), "IkOptions: min_height must be finite");
  require(std::isfinite(base_clearance) && base_clearance >= 0,
          "IkOptions: base_clearance must be >= 0");
  require(max_iterations > 0, "IkOptions: max_iterations must be > 0");
  require(tolerance > 0 && tolerance < 1e-2, "IkOptions: tolerance must be in (0, 0.01) m");
  require(initial_damping > 0 && std::isfinite(initial_damping),
          "IkOptions: initial_damping must be > 0");
  require(pitch_weight > 0 && std::isfinite(pitch_weight), "IkOptions: pitch_weight must be > 0");
}

PitchWindow reachable_pitch(const ArmGeometry& g, double radial, double height) {
  PitchWindow w;
  const Eigen::Vector2d D = Eigen::Vector2d(radial, height) - g.shoulder;
  const double dn = D.norm();
  const double outer = g.upper_arm + g.forearm;
  const double inner = std::abs(g.upper_arm - g.forearm);
  if (dn < 1e-12) {
    // The wrist circles the shoulder at distance |hand| whatever the pitch.
    if (g.hand >= inner && g.hand <= outer) {
      w.lo = 0;
      w.hi = kPi;
    }
    return w;
  }
  w.phi = std::atan2(D.y(), D.x());
  // |wrist - shoulder|^2 = |D|^2 + hand^2 - 2 hand |D| cos(delta) must lie in [inner^2, outer^2].
  const double k_out = (dn * dn + g.hand * g.hand - outer * outer) / (2 * g.hand * dn);
  const double k_in = (dn * dn + g.hand * g.hand - inner * inner) / (2 * g.hand * dn);
  constexpr double kSlack = 1e-12;
  if (k_out > 1 + kSlack || k_in < -1 - kSlack) return w;  // empty
  w.hi = std::acos(std::clamp(k_out, -1.0, 1.0));
  w.lo = std::acos(std::clamp(k_in, -1.0, 1.0));
  return w;
}

IkResult solve_ik(ArmState& state, const Eigen::Vector3d& target, const JointVector& q_start,
                  const IkOptions& options) {
  options.validate();
  require(q_start.allFinite(), "IK start configuration is not finite");
  check_target(state.arm(), target, options);
  switch (options.method) {
    case IkMethod::analytic:
      return solve_analytic(state, target, q_start, options);
    case IkMethod::numerical:
      return solve_numerical(state, target, q_start, options);
    case IkMethod::automatic:
      break;
  }
  if (state.arm().geometry().analytic) return solve_analytic(state, target, q_start, options);
  return solve_numerical(state, target, q_start, options);
}

}  // namespace proprio::robot
