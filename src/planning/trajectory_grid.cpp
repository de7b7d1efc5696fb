#include "proprio/planning/trajectory_grid.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <thread>

#include "proprio/core/error.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/logging.hpp"
#include "proprio/core/parallel.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/core/random.hpp"
#include "proprio/robot/dynamics.hpp"
#include "text.hpp"

namespace proprio::planning {

using detail::cat;
namespace fs = std::filesystem;

double GridAxis::value(int i) const {
  return count <= 1 ? min : min + (max - min) * i / (count - 1);
}

robot::TrajectoryParams GridSpec::params(int index) const {
  const int ig = index % gamma.count;
  const int il = (index / gamma.count) % length.count;
  const int it = index / (gamma.count * length.count);
  return {theta.value(it), length.value(il), gamma.value(ig)};
}

Eigen::Vector3d GridSpec::end_point(const robot::TrajectoryParams& psi) const {
  return start + psi.length * Eigen::Vector3d(std::sin(psi.theta), std::cos(psi.theta), 0);
}

robot::BezierTrajectory GridSpec::trajectory(const robot::TrajectoryParams& psi) const {
  return robot::psi_trajectory(start, psi, duration);
}

void GridSpec::validate() const {
  require(start.allFinite(), "GridSpec: start must be finite");
  require(std::isfinite(duration) && duration > 0 && duration <= 60,
          "GridSpec: duration must be in (0, 60] s");
  for (const GridAxis* a : {&theta, &length, &gamma}) {
    require(a->count >= 1 && a->count <= 1000, "GridSpec: axis counts must be in [1, 1000]");
    require(std::isfinite(a->min) && std::isfinite(a->max) && a->min <= a->max,
            "GridSpec: axis ranges must be finite with min <= max");
  }
  require(length.min > 0, "GridSpec: lengths must be > 0 m");
}

void GridCostOptions::validate() const {
  grid.validate();
  motion.validate();
  require(std::isfinite(rate_hz) && rate_hz >= 10 && rate_hz <= 10000,
          "GridCostOptions: rate_hz must be in [10, 10000]");
  require(precision_samples >= 2 && precision_samples <= 100000,
          "GridCostOptions: precision_samples must be in [2, 100000]");
  require(std::isfinite(perturbation_std) && perturbation_std > 0,
          "GridCostOptions: perturbation_std must be > 0 m");
  require(std::isfinite(snr_eps) && snr_eps > 0, "GridCostOptions: snr_eps must be > 0 N m");
  require(threads >= 0 && threads <= 256, "GridCostOptions: threads must be in [0, 256]");
}

namespace {

// FNV-1a, 64 bits: a fingerprint, not a security measure.
struct Fnv {
  std::uint64_t h = 1469598103934665603ull;
  void add(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  }
  void add(const std::string& s) { add(s.data(), s.size() + 1); }
  void add(double v) {
    char buf[40];
    const int n = std::snprintf(buf, sizeof buf, "%.17g;", v);
    add(buf, static_cast<std::size_t>(n));
  }
};

// The Bezier of eq 3.40 through a given end point (the perturbed one of eq 3.42).
robot::BezierTrajectory bezier_to(const Eigen::Vector3d& p0, const Eigen::Vector3d& p2,
                                  double gamma, double duration) {
  const Eigen::Vector3d d = p2 - p0;
  const Eigen::Vector3d perp(-d.y(), d.x(), 0);
  return robot::BezierTrajectory(p0, p0 + 0.5 * d + gamma * perp, p2, duration);
}

std::vector<robot::JointVector> torques_along(robot::ArmState& state,
                                              const robot::CartesianTrajectory& path,
                                              const robot::JointVector& q0,
                                              const GridCostOptions& o, double* dt) {
  const robot::TrackResult track = track_scheduled(state, path, q0, o.rate_hz, o.motion);
  *dt = track.joints.dt;
  return robot::inverse_dynamics(state, track.joints);
}

GridPoint cost_of(robot::ArmState& state, const robot::JointVector& q0, int index,
                  const GridCostOptions& o) {
  const GridSpec& g = o.grid;
  GridPoint p;
  p.psi = g.params(index);
  double dt = 0;
  std::vector<robot::JointVector> tau;
  try {
    tau = torques_along(state, g.trajectory(p.psi), q0, o, &dt);
  } catch (const Error& e) {
    p.why_invalid = e.what();
    return p;
  }
  const robot::Energy E = robot::energy(tau, dt);  // eq 3.41
  p.energy_per_joint = E.per_joint;
  p.energy = E.total;

  // Precision (eq 3.42): torque statistics over perturbed end points, per joint and sample.
  auto rng = core::Rng::stream(o.seed, static_cast<std::uint64_t>(index));
  const Eigen::Vector3d p2 = g.end_point(p.psi);
  const std::size_t n = tau.size();
  std::vector<robot::JointVector> sum(n, robot::JointVector::Zero());
  std::vector<robot::JointVector> sum_sq(n, robot::JointVector::Zero());
  for (int k = 0; k < o.precision_samples; ++k) {
    const Eigen::Vector3d p2k =
        p2 + o.perturbation_std * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    std::vector<robot::JointVector> tk;
    try {
      tk = torques_along(state, bezier_to(g.start, p2k, p.psi.gamma, g.duration), q0, o, &dt);
    } catch (const Error&) {
      continue;  // an unreachable perturbation: left out
    }
    if (tk.size() != n) continue;
    for (std::size_t i = 0; i < n; ++i) {
      sum[i] += tk[i];
      sum_sq[i] += tk[i].cwiseProduct(tk[i]);
    }
    ++p.samples_used;
  }
  if (2 * p.samples_used < o.precision_samples) {
    p.why_invalid =
        cat({"only ", std::to_string(p.samples_used), " of ", std::to_string(o.precision_samples),
             " perturbed end points are reachable"});
    return p;
  }
  const double m = p.samples_used;
  for (std::size_t i = 0; i < n; ++i) {
    const robot::JointVector mean = sum[i] / m;
    const robot::JointVector var =
        ((sum_sq[i] - m * mean.cwiseProduct(mean)) / (m - 1)).cwiseMax(0.0);
    const robot::JointVector snr =
        mean.cwiseAbs().cwiseQuotient((var.cwiseSqrt().array() + o.snr_eps).matrix());
    const double w = (i == 0 || i + 1 == n) ? 0.5 * dt : dt;  // trapezoid rule
    p.rho_per_joint += w * snr;
  }
  p.rho = p.rho_per_joint.sum();
  p.valid = std::isfinite(p.energy) && std::isfinite(p.rho) && p.rho > 0;
  if (!p.valid) p.why_invalid = "non-finite cost";
  return p;
}

void finish(GridCosts& c) {
  std::vector<double> rho;
  c.summary.valid = c.summary.invalid = 0;
  for (const GridPoint& p : c.points) {
    if (p.valid) {
      ++c.summary.valid;
      rho.push_back(p.rho);
    } else {
      ++c.summary.invalid;
    }
  }
  c.summary.median_rho = 0;
  c.sigma_scale = 0;
  if (!rho.empty()) {
    std::sort(rho.begin(), rho.end());
    const std::size_t h = rho.size() / 2;
    c.summary.median_rho = rho.size() % 2 ? rho[h] : 0.5 * (rho[h - 1] + rho[h]);
    // eq 3.43: Sigma_psi = c / rho, c such that the median trajectory gets the perturbation's std.
    const double s = c.options.perturbation_std;
    c.sigma_scale = s * s * c.summary.median_rho;
  }
}

core::Json joints_json(const robot::JointVector& v) {
  return core::Json(std::vector<double>(v.data(), v.data() + v.size()));
}

}  // namespace

std::string grid_cache_key(const robot::Arm& arm, const GridCostOptions& o) {
  Fnv f;
  f.add(std::string("proprio.intercept.grid_costs"));
  f.add(static_cast<double>(kGridCacheVersion));
  const mjModel& m = arm.model();
  std::vector<char> mjb(static_cast<std::size_t>(mj_sizeModel(&m)));
  mj_saveModel(&m, nullptr, mjb.data(), static_cast<int>(mjb.size()));
  f.add(mjb.data(), mjb.size());
  const robot::ArmNames& n = arm.names();
  for (const auto& s : n.joints) f.add(s);
  for (const auto& s : n.actuators) f.add(s);
  f.add(n.ee_site);
  const GridSpec& g = o.grid;
  for (double v : {g.start.x(),
                   g.start.y(),
                   g.start.z(),
                   g.duration,
                   g.theta.min,
                   g.theta.max,
                   static_cast<double>(g.theta.count),
                   g.length.min,
                   g.length.max,
                   static_cast<double>(g.length.count),
                   g.gamma.min,
                   g.gamma.max,
                   static_cast<double>(g.gamma.count),
                   o.motion.preferred_pitch,
                   o.motion.pitch_margin,
                   o.motion.max_joint_speed,
                   o.rate_hz,
                   static_cast<double>(o.precision_samples),
                   o.perturbation_std,
                   o.snr_eps,
                   static_cast<double>(o.seed)}) {
    f.add(v);
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(f.h));
  return buf;
}

GridCosts compute_grid_costs(const robot::Arm& arm, const GridCostOptions& options,
                             bool show_progress) {
  options.validate();
  const auto t0 = std::chrono::steady_clock::now();
  GridCosts c;
  c.options = options;
  c.key = grid_cache_key(arm, options);
  const int n = options.grid.size();
  c.points.resize(static_cast<std::size_t>(n));
  robot::ArmState probe(arm);
  robot::JointVector q0;
  try {
    q0 = solve_scheduled(probe, options.grid.start, arm.clamp(robot::JointVector::Zero()),
                         options.motion)
             .q;
  } catch (const Error& e) {
    throw Error(cat({"the grid's start point is unreachable: ", e.what()}));
  }
  const auto tasks = static_cast<std::size_t>(n);
  const int threads = core::thread_count(options.threads, tasks);
  core::ProgressBar bar(tasks, "trajectory costs", show_progress);
  std::mutex bar_mutex;
  // One MuJoCo workspace per thread; each trajectory's cost depends only on its index.
  std::vector<robot::ArmState> states;
  states.reserve(static_cast<std::size_t>(threads));
  for (int t = 0; t < threads; ++t) states.emplace_back(arm);
  core::parallel_for(tasks, threads, [&](std::size_t i, int thread) {
    c.points[i] =
        cost_of(states[static_cast<std::size_t>(thread)], q0, static_cast<int>(i), options);
    const std::lock_guard<std::mutex> lock(bar_mutex);
    bar.tick();
  });
  bar.finish();
  finish(c);
  c.summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  c.summary.source = "computed";
  return c;
}

void write_grid_costs(const fs::path& path, const GridCosts& c) {
  const GridCostOptions& o = c.options;
  const GridSpec& g = o.grid;
  core::Json j;
  j["format"] = "proprio.intercept.grid_costs";
  j["format_version"] = kGridCacheVersion;
  j["key"] = c.key;
  auto axis = [](const GridAxis& a) {
    return core::Json{{"min", a.min}, {"max", a.max}, {"count", a.count}};
  };
  j["grid"] = {{"start", {g.start.x(), g.start.y(), g.start.z()}},
               {"duration", g.duration},
               {"theta", axis(g.theta)},
               {"length", axis(g.length)},
               {"gamma", axis(g.gamma)}};
  j["options"] = {{"preferred_pitch", o.motion.preferred_pitch},
                  {"pitch_margin", o.motion.pitch_margin},
                  {"max_joint_speed", o.motion.max_joint_speed},
                  {"rate_hz", o.rate_hz},
                  {"precision_samples", o.precision_samples},
                  {"perturbation_std", o.perturbation_std},
                  {"snr_eps", o.snr_eps},
                  {"seed", o.seed}};
  j["sigma_scale"] = c.sigma_scale;
  j["compute_seconds"] = c.summary.seconds;
  core::Json points = core::Json::array();
  for (const GridPoint& p : c.points) {
    points.push_back({{"theta", p.psi.theta},
                      {"length", p.psi.length},
                      {"gamma", p.psi.gamma},
                      {"valid", p.valid},
                      {"why_invalid", p.why_invalid},
                      {"energy", p.energy},
                      {"energy_per_joint", joints_json(p.energy_per_joint)},
                      {"rho", p.rho},
                      {"rho_per_joint", joints_json(p.rho_per_joint)},
                      {"samples_used", p.samples_used}});
  }
  j["points"] = std::move(points);
  core::write_json_atomic(path, j);
}

namespace {

double finite(const core::Json& j, const std::string& key, const fs::path& file) {
  const double v = core::json_get<double>(j, key, file);
  if (!std::isfinite(v)) throw Error::in_file(file, cat({"'", key, "' is not finite"}));
  return v;
}

robot::JointVector joints_from(const core::Json& j, const std::string& key, const fs::path& file) {
  const auto v = core::json_get<std::vector<double>>(j, key, file);
  if (v.size() != static_cast<std::size_t>(robot::kArmJoints)) {
    throw Error::in_file(
        file, cat({"'", key, "' must hold ", std::to_string(robot::kArmJoints), " numbers"}));
  }
  robot::JointVector out;
  for (int k = 0; k < robot::kArmJoints; ++k) {
    out[k] = v[static_cast<std::size_t>(k)];
    if (!std::isfinite(out[k])) throw Error::in_file(file, cat({"'", key, "' is not finite"}));
  }
  return out;
}

GridAxis axis_from(const core::Json& j, const std::string& key, const fs::path& file) {
  const core::Json a = core::json_get<core::Json>(j, key, file);
  return {finite(a, "min", file), finite(a, "max", file), core::json_get<int>(a, "count", file)};
}

}  // namespace

GridCosts read_grid_costs(const fs::path& path) {
  const core::Json j = core::read_json(path);
  if (!j.is_object()) throw Error::in_file(path, "not a JSON object");
  const auto format = core::json_get<std::string>(j, "format", path);
  if (format != "proprio.intercept.grid_costs") {
    throw Error::in_file(
        path, cat({"format is '", format, "', expected 'proprio.intercept.grid_costs'"}));
  }
  const int version = core::json_get<int>(j, "format_version", path);
  if (version != kGridCacheVersion) {
    throw Error::in_file(path, cat({"format_version ", std::to_string(version),
                                    " is not supported (this build reads ",
                                    std::to_string(kGridCacheVersion), ")"}));
  }
  GridCosts c;
  c.key = core::json_get<std::string>(j, "key", path);
  const core::Json g = core::json_get<core::Json>(j, "grid", path);
  GridSpec& s = c.options.grid;
  const auto start = core::json_get<std::vector<double>>(g, "start", path);
  if (start.size() != 3) throw Error::in_file(path, "'start' must hold 3 numbers");
  s.start = {start[0], start[1], start[2]};
  s.duration = finite(g, "duration", path);
  s.theta = axis_from(g, "theta", path);
  s.length = axis_from(g, "length", path);
  s.gamma = axis_from(g, "gamma", path);
  const core::Json o = core::json_get<core::Json>(j, "options", path);
  c.options.motion.preferred_pitch = finite(o, "preferred_pitch", path);
  c.options.motion.pitch_margin = finite(o, "pitch_margin", path);
  c.options.motion.max_joint_speed = finite(o, "max_joint_speed", path);
  c.options.rate_hz = finite(o, "rate_hz", path);
  c.options.precision_samples = core::json_get<int>(o, "precision_samples", path);
  c.options.perturbation_std = finite(o, "perturbation_std", path);
  c.options.snr_eps = finite(o, "snr_eps", path);
  c.options.seed = core::json_get<std::uint64_t>(o, "seed", path);
  try {
    c.options.validate();
  } catch (const Error& e) {
    throw Error::in_file(path, e.what());
  }
  const core::Json points = core::json_get<core::Json>(j, "points", path);
  if (!points.is_array() || static_cast<int>(points.size()) != s.size()) {
    throw Error::in_file(
        path, cat({"'points' must be an array of ", std::to_string(s.size()), " grid points"}));
  }
  for (const core::Json& p : points) {
    GridPoint q;
    q.psi = {finite(p, "theta", path), finite(p, "length", path), finite(p, "gamma", path)};
    q.valid = core::json_get<bool>(p, "valid", path);
    q.why_invalid = core::json_get<std::string>(p, "why_invalid", path);
    q.energy = finite(p, "energy", path);
    q.energy_per_joint = joints_from(p, "energy_per_joint", path);
    q.rho = finite(p, "rho", path);
    q.rho_per_joint = joints_from(p, "rho_per_joint", path);
    q.samples_used = core::json_get<int>(p, "samples_used", path);
    if (q.valid && !(q.energy > 0 && q.rho > 0)) {
      throw Error::in_file(path, "a valid grid point has a non-positive energy or precision");
    }
    c.points.push_back(q);
  }
  c.options.threads = 0;
  finish(c);
  c.summary.source = "cache";
  return c;
}

GridCosts load_or_compute_grid_costs(const robot::Arm& arm, const GridCostOptions& options,
                                     const fs::path& cache, bool show_progress) {
  const std::string key = grid_cache_key(arm, options);
  std::string why;
  if (fs::exists(cache)) {
    try {
      GridCosts c = read_grid_costs(cache);
      if (c.key == key) {
        c.options.threads = options.threads;
        return c;
      }
      why = "stale: the arm model or the grid changed";
    } catch (const Error& e) {
      why = cat({"unreadable: ", e.what()});
    }
    spdlog::warn("trajectory cost cache {} is {}; recomputing", cache.string(), why);
  } else {
    why = "absent";
  }
  GridCosts c = compute_grid_costs(arm, options, show_progress);
  write_grid_costs(cache, c);
  c.summary.source = cat({"computed (cache ", why, ")"});
  return c;
}

// ---- GridCostModel --------------------------------------------------------------------------

namespace {

// Catmull-Rom weights of the four neighbours (i-1, i, i+1, i+2) at fraction u of cell i.
std::array<double, 4> catmull_rom(double u) {
  const double u2 = u * u, u3 = u2 * u;
  return {0.5 * (-u3 + 2 * u2 - u), 0.5 * (3 * u3 - 5 * u2 + 2), 0.5 * (-3 * u3 + 4 * u2 + u),
          0.5 * (u3 - u2)};
}

// Cell and fraction of x on an axis (x already clamped).
void locate(const GridAxis& a, double x, int* cell, double* u) {
  if (a.count <= 1 || a.max <= a.min) {
    *cell = 0;
    *u = 0;
    return;
  }
  const double s = (x - a.min) / (a.max - a.min) * (a.count - 1);
  *cell = std::clamp(static_cast<int>(std::floor(s)), 0, a.count - 2);
  *u = s - *cell;
}

}  // namespace

GridCostModel::GridCostModel(GridCosts costs) : costs_(std::move(costs)) {
  const GridSpec& g = grid();
  g.validate();
  require(static_cast<int>(costs_.points.size()) == g.size(),
          "trajectory costs: the point count does not match the grid");
  double worst_e = -1e300, worst_r = 1e300;
  for (const GridPoint& p : costs_.points) {
    if (!p.valid) continue;
    worst_e = std::max(worst_e, std::log(p.energy));
    worst_r = std::min(worst_r, std::log(p.rho));
  }
  require(worst_e > -1e300, "trajectory costs: no trajectory of the grid can be tracked");
  require(costs_.sigma_scale > 0, "trajectory costs: the precision scale is not positive");
  for (const GridPoint& p : costs_.points) {
    log_energy_.push_back(p.valid ? std::log(p.energy) : worst_e + 1);
    log_rho_.push_back(p.valid ? std::log(p.rho) : worst_r - 1);
  }
}

Eigen::Vector3d GridCostModel::clamp(const Eigen::Vector3d& psi) const {
  const GridSpec& g = grid();
  return {std::clamp(psi.x(), g.theta.min, g.theta.max),
          std::clamp(psi.y(), g.length.min, g.length.max),
          std::clamp(psi.z(), g.gamma.min, g.gamma.max)};
}

double GridCostModel::interpolate(const std::vector<double>& values,
                                  const Eigen::Vector3d& psi_in) const {
  const GridSpec& g = grid();
  const Eigen::Vector3d psi = clamp(psi_in);
  int ct, cl, cg;
  double ut, ul, ug;
  locate(g.theta, psi.x(), &ct, &ut);
  locate(g.length, psi.y(), &cl, &ul);
  locate(g.gamma, psi.z(), &cg, &ug);
  const auto wt = catmull_rom(ut), wl = catmull_rom(ul), wg = catmull_rom(ug);
  double sum = 0;
  for (int a = 0; a < 4; ++a) {
    const int it = std::clamp(ct + a - 1, 0, g.theta.count - 1);
    for (int b = 0; b < 4; ++b) {
      const int il = std::clamp(cl + b - 1, 0, g.length.count - 1);
      const double wab = wt[static_cast<std::size_t>(a)] * wl[static_cast<std::size_t>(b)];
      for (int c = 0; c < 4; ++c) {
        const int ig = std::clamp(cg + c - 1, 0, g.gamma.count - 1);
        sum += wab * wg[static_cast<std::size_t>(c)] *
               values[static_cast<std::size_t>(g.index(it, il, ig))];
      }
    }
  }
  return sum;
}

double GridCostModel::log_energy(const Eigen::Vector3d& psi) const {
  return interpolate(log_energy_, psi);
}

double GridCostModel::log_rho(const Eigen::Vector3d& psi) const {
  return interpolate(log_rho_, psi);
}

double GridCostModel::arm_variance(const Eigen::Vector3d& psi) const {
  return costs_.sigma_scale * std::exp(-log_rho(psi));
}

}  // namespace proprio::planning
