// Suspension points from the Lees–Edwards box (see box_point.hpp).
#include "rheosim/rheometer/box_point.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <future>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <thread>

#include <fmt/format.h>

#include "rheosim/dem/size_distribution.hpp"
#include "rheosim/numerics/quadrature.hpp"
#include "rheosim/rheometer/plate.hpp"
#include "rheosim/rheometer/shear_cell.hpp"

namespace rheosim::rheometer {
namespace {

constexpr double pi = std::numbers::pi;

// St and Re_p by the one definition of shear_cell.hpp's dimensionless_groups().
double stokes_number(const RheometerCase& r, double rate) {
  return dimensionless_groups(r, r.fluid, *r.particles, rate).stokes;
}

// The box runs the case's near field when it has lubrication, else the predictive default.
bool near_field_from_case(const RheometerCase& r) {
  return r.particles->hydrodynamics_given && r.particles->hydrodynamics.terms.lubrication;
}

coupling::NearFieldSettings box_near_field(const RheometerCase& r) {
  if (near_field_from_case(r)) return r.particles->hydrodynamics;
  coupling::NearFieldSettings h;
  h.terms.lubrication = true;
  h.terms.single_particle = true;
  h.roughness = 1.0e-3;
  h.lubrication_cutoff = coupling::SuspensionBoxSettings{}.lubrication_cutoff;
  return h;
}

// One box run and what the points of its rate need from it.
struct BoxRun {
  double rate = 0.0;
  coupling::SuspensionBoxResult result;
};

}  // namespace

bool box_has_walls(const RheometerCase& r) {
  using Model = RheometerCase::SuspensionModel;
  if (r.suspension_model == Model::walled_box) return true;
  return r.suspension_model == Model::automatic && r.particles &&
         r.geometry.gap < walled_box_gap_limit * r.particles->diameter;
}

coupling::SuspensionBoxSettings box_settings(const RheometerCase& r, double phi, double rate) {
  const auto& p = *r.particles;
  const auto& matrix = *r.fluid.rheology;
  const double a = 0.5 * p.diameter;
  const double mu = matrix.viscosity(rate);
  coupling::SuspensionBoxSettings s;
  s.volume_fraction = phi;
  s.friction = p.friction;
  if (box_has_walls(r)) s.wall_gap = r.geometry.gap / a;
  const double st = stokes_number(r, rate);
  s.stokes_number = st <= overdamped_stokes_limit ? 0.0 : st;
  const coupling::NearFieldSettings h = box_near_field(r);
  s.roughness = h.roughness;
  s.lubrication_cutoff = h.lubrication_cutoff;
  if (h.terms.repulsion) {
    s.repulsion_force = h.repulsion_force / (6.0 * pi * mu * a * a * rate);
    s.repulsion_length = h.repulsion_length;
  }
  if (matrix.name() != "newtonian") {
    const auto rheology = r.fluid.rheology;
    s.viscosity_ratio = [rheology, rate, mu](double ratio) { return rheology->viscosity(ratio * rate) / mu; };
    // Chateau, Ovarlez & Trung's homogenised stresslet viscosity (near_field.cpp): μ + 0.7 γ̇ dμ/dγ̇.
    if (h.stresslet_viscosity == coupling::StressletViscosity::homogenized) {
      const double tangent = mu + rate * matrix.viscosity_derivative(rate);
      s.stresslet_viscosity_ratio = std::isfinite(tangent) ? 0.3 + 0.7 * std::max(tangent, 0.0) / mu : 1.0;
    }
  }
  if (p.size_distribution.type != dem::SizeDistribution::Type::none) {
    // The case's sizes: sample the spheres of a box of the default count, relative to d.
    const double volume = s.particles * pi / 6.0 * p.diameter * p.diameter * p.diameter;
    const auto diameters = dem::sample_diameters(p.size_distribution, p.diameter, volume, 1);
    s.radii.clear();
    s.volume_shares.clear();
    double total = 0.0;
    for (const double d : diameters) total += d * d * d;
    for (const double d : diameters) {
      s.radii.push_back(d / p.diameter);
      s.volume_shares.push_back(d * d * d / total);
    }
    s.particles = static_cast<int>(diameters.size());
  }
  return s;
}

bool box_is_rate_independent(const RheometerCase& r) {
  if (r.fluid.rheology->name() != "newtonian") return false;
  if (box_near_field(r).terms.repulsion) return false;
  for (const double rate : r.shear_rates)
    if (stokes_number(r, rate) > overdamped_stokes_limit) return false;
  return true;
}

std::string describe_box(const RheometerCase& r, double phi) {
  const double low = r.shear_rates.front(), high = r.shear_rates.back();
  const auto s = box_settings(r, phi, high);
  const double st_low = stokes_number(r, low), st_high = stokes_number(r, high);
  const auto& p = *r.particles;
  const double re_high = dimensionless_groups(r, r.fluid, p, high).particle_reynolds;
  const coupling::NearFieldSettings h = box_near_field(r);
  return fmt::format(
      "{} of {} spheres ({}), {} integrator (St = (2/9)ρ_p a²γ̇/μ = {:.3g}–{:.3g}{} {:g}), near field "
      "{}: lubrication (roughness δ/ā {:g}, cutoff h_c/ā {:g}) + isolated-sphere drag, rotation and stresslet{}, "
      "contacts k_n = {:g}·6πμaγ̇ with friction μ_c = {:g}; Re_p = ρ γ̇ a²/μ up to {:.3g}; H/d = {:.3g}; {}",
      s.wall_gap > 0.0 ? fmt::format("walled box (plates H = {:g} d apart, periodic across, the liquid's mean "
                                     "velocity carrying the spheres' drag)",
                                     r.geometry.gap / p.diameter)
                       : std::string("Lees–Edwards box"),
      s.particles,
      p.size_distribution.type == dem::SizeDistribution::Type::none ? "equal spheres" : "the case's size distribution",
      st_high <= overdamped_stokes_limit ? "overdamped (inertialess, strain units)"
                                         : "inertial (implicit, strain units)",
      st_low, st_high, st_high <= overdamped_stokes_limit ? " <=" : ", above", overdamped_stokes_limit,
      near_field_from_case(r) ? "from particles.hydrodynamics" : "by default", s.roughness, s.lubrication_cutoff,
      s.repulsion_force > 0.0 ? fmt::format(" + repulsion F_R0 = {:g} N", h.repulsion_force) : std::string(),
      s.contact_stiffness > 0.0 ? s.contact_stiffness : coupling::default_contact_stiffness(phi), s.friction, re_high,
      r.geometry.gap / p.diameter,
      box_is_rate_independent(r) ? "the same dimensionless box serves every rate (Newtonian, overdamped)"
                                 : "one box per rate");
}

double plate_normal_force(const std::vector<double>& rates, const std::vector<double>& n12, double radius,
                          double rim_rate) {
  if (rates.empty()) return std::nan("");
  // (N1 − N2)(s) as ratio c(s) = ΔN/s, linear in s between the measured rates, constant outside.
  const auto ratio = [&](double s) {
    if (s <= rates.front()) return n12.front() / rates.front();
    if (s >= rates.back()) return n12.back() / rates.back();
    std::size_t k = 0;
    while (rates[k + 1] < s) ++k;
    const double t = (s - rates[k]) / (rates[k + 1] - rates[k]);
    return (1.0 - t) * n12[k] / rates[k] + t * n12[k + 1] / rates[k + 1];
  };
  std::vector<double> edges{0.0};
  for (const double s : rates)
    if (s > 0.0 && s < rim_rate) edges.push_back(s);
  edges.push_back(rim_rate);
  double integral = 0.0;  // ∫₀^γ̇_R ΔN(s) s ds = ∫ c(s) s² ds
  for (std::size_t k = 0; k + 1 < edges.size(); ++k)
    integral +=
        numerics::integrate_gauss_legendre<8>(edges[k], edges[k + 1], [&](double s) { return ratio(s) * s * s; });
  return pi * radius * radius / (rim_rate * rim_rate) * integral;
}

namespace {

// Runs queued boxes on up to one worker per core; each job's result through a shared future.
class BoxPool {
 public:
  using Future = std::shared_future<coupling::SuspensionBoxResult>;
  ~BoxPool() {
    {
      const std::lock_guard lock(mutex_);
      stop_ = true;
      queue_.clear();  // unstarted jobs are dropped; nobody waits for them any more
    }
    wake_.notify_all();
    for (auto& w : workers_) w.join();
  }
  Future submit(coupling::SuspensionBoxSettings settings) {
    std::packaged_task<coupling::SuspensionBoxResult()> task(
        [s = std::move(settings)] { return coupling::run_suspension_box(s); });
    Future future = task.get_future().share();
    {
      const std::lock_guard lock(mutex_);
      queue_.push_back(std::move(task));
      const std::size_t cores = std::max(1U, std::thread::hardware_concurrency());
      if (workers_.size() < cores) workers_.emplace_back([this] { work(); });
    }
    wake_.notify_one();
    return future;
  }

 private:
  void work() {
    for (;;) {
      std::packaged_task<coupling::SuspensionBoxResult()> task;
      {
        std::unique_lock lock(mutex_);
        wake_.wait(lock, [this] { return stop_ || !queue_.empty(); });
        if (queue_.empty()) return;
        task = std::move(queue_.front());
        queue_.pop_front();
      }
      task();  // an exception is stored in the future
    }
  }
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::packaged_task<coupling::SuspensionBoxResult()>> queue_;
  std::vector<std::thread> workers_;
  bool stop_ = false;
};

class BoxRunner {
 public:
  BoxRunner(RheometerCase r, std::vector<double> volume_fractions)
      : r_(std::move(r)), volume_fractions_(std::move(volume_fractions)) {}

  // No strain progress: a box runs on a worker, perhaps before its point is asked for.
  PointResult run(const SweepPoint& point) {
    PointResult out;
    const bool walls = box_has_walls(r_);
    out.model = walls ? "walled_box" : "lees_edwards";
    out.method = walls ? "walled suspension box (the plates at the case's gap: lubrication, isolated-sphere drag and "
                         "stresslet, frictional contacts with spheres and plates), torque and normal force from the "
                         "local flow curve"
                       : "Lees–Edwards suspension box (bulk stress: lubrication, isolated-sphere drag and stresslet, "
                         "frictional contacts), torque and normal force from the local flow curve";
    if (!r_.particles) {
      out.failure = fmt::format("φ = {:g} needs a particles: section", point.volume_fraction);
      return out;
    }
    const auto start = std::chrono::steady_clock::now();
    bool fresh = false;
    const std::vector<BoxRun>* runs = nullptr;
    try {
      runs = &runs_for(point.volume_fraction, fresh);
    } catch (const std::exception& e) {
      out.failure = fmt::format("suspension box failed: {}", e.what());
      return out;
    }
    const double rate = point.rim_shear_rate;
    const auto& matrix = *r_.fluid.rheology;
    // Local flow curve and normal-stress curve in SI from the dimensionless boxes.
    LocalFlowCurve curve;
    std::vector<double> n12;  // N1 − N2 at curve.shear_rate
    bool all_converged = true;
    const BoxRun* nearest = &runs->front();
    double statistical = 0.0;
    for (const auto& run : *runs) {
      const auto rates_of_run = run.rate > 0.0 ? std::vector<double>{run.rate} : r_.shear_rates;
      for (const double s : rates_of_run) {
        const double scale = matrix.viscosity(s) * s;  // μ(γ̇)γ̇ [Pa]
        curve.shear_rate.push_back(s);
        curve.stress.push_back(run.result.relative_viscosity.mean * scale);
        n12.push_back((run.result.n1.mean - run.result.n2.mean) * scale);
      }
      all_converged = all_converged && run.result.converged;
      statistical = std::max(statistical, run.result.relative_viscosity.error / run.result.relative_viscosity.mean);
      if (run.rate == rate) nearest = &run;
    }
    const bool linear = runs->size() == 1 && runs->front().rate == 0.0;
    if (linear) {
      curve.linear = true;
      curve.viscosity = runs->front().result.relative_viscosity.mean * matrix.viscosity(rate);
    }
    const auto& b = nearest->result;
    const double scale = matrix.viscosity(rate) * rate;
    out.torque = plate_torque(curve, r_.geometry.radius, rate);
    out.torque_creeping = out.torque;
    out.torque_std_error = out.torque * b.relative_viscosity.error / b.relative_viscosity.mean;
    const double eta = b.relative_viscosity.mean;
    out.torque_fluid = out.torque * b.part_fluid / eta;
    out.torque_contact = out.torque * b.part_contact / eta;
    out.torque_lubrication = out.torque * (b.part_lubrication + b.part_repulsion) / eta;
    out.torque_stresslet = out.torque * b.part_stresslet / eta;
    out.torque_couple = 0.0;
    out.normal_force = plate_normal_force(curve.shear_rate, n12, r_.geometry.radius, rate);
    out.n1 = b.n1.mean * scale;
    out.n2 = b.n2.mean * scale;
    out.strain = b.strain;
    out.estimated_error = statistical;
    out.converged = std::isfinite(out.torque);
    if (!out.converged) out.failure = "the suspension box gave no finite stress";
    out.warnings = b.warnings;
    if (!all_converged && b.converged)
      out.warnings.push_back("suspension box: a box of another rate of this φ did not reach its averaging tolerance");
    const auto& p = *r_.particles;
    const double re_p = dimensionless_groups(r_, r_.fluid, p, rate).particle_reynolds;
    if (re_p > particle_reynolds_limit)
      out.warnings.push_back(fmt::format(
          "particle Reynolds number ρ γ̇ a²/μ = {:.3g} > {:g}: the box solves Stokes flow around each sphere; fluid "
          "inertia at the particle scale is not modelled",
          re_p, particle_reynolds_limit));
    if (!walls && r_.geometry.gap < walled_box_gap_limit * p.diameter)
      out.warnings.push_back(fmt::format(
          "H/d = {:.3g} < {:g}: the Lees–Edwards box gives the bulk stress; the layering and slip at the plates of a "
          "gap of a few diameters are left out (model: walled_box simulates them)",
          r_.geometry.gap / p.diameter, walled_box_gap_limit));
    out.model_reason = fmt::format(
        "{}; box at {}: η_r {:.4g} ± {:.2g} (liquid 1 + stresslet {:.3g} + lubrication {:.3g} + contact {:.3g}{}), "
        "N1 {:.3g} μγ̇, N2 {:.3g} μγ̇, particle pressure {:.3g} μγ̇; {} spheres, strain {:.3g} (averaged {:.3g}, Δγ "
        "{:.2g}), {:.3g} contacts per sphere ({:.0f} % sliding), overlap mean {:.2g} / max {:.2g} ā, {:.1f} solver "
        "iterations per step, {:.1f} s{}",
        describe_box(r_, point.volume_fraction),
        nearest->rate > 0.0 ? fmt::format("{:g} 1/s", nearest->rate) : "every rate", eta, b.relative_viscosity.error,
        b.part_stresslet, b.part_lubrication, b.part_contact,
        b.part_repulsion != 0.0 ? fmt::format(" + repulsion {:.3g}", b.part_repulsion) : std::string(), b.n1.mean,
        b.n2.mean, b.particle_pressure.mean, b.particles, b.strain, b.averaged_strain, b.strain_step,
        b.mean_contacts_per_particle, 100.0 * b.sliding_fraction, b.mean_overlap, b.max_overlap,
        b.mean_solver_iterations, b.wall_time,
        walls
            ? fmt::format("; plates: box {:.3g} × {:.3g} × {:.3g} ā, liquid shear rate {:.3g} γ̇ in the middle third "
                          "and {:.3g} γ̇ within ā of the plates, near-plate spheres lag u∞ by {:.3g} āγ̇",
                          b.box_length, b.box_length, b.box_height, b.core_shear_rate, b.plate_shear_rate, b.wall_slip)
            : std::string());
    out.iterations = fresh ? static_cast<int>(runs->size()) : 0;
    out.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
  }

 private:
  // The boxes of φ, waiting for them; the first call for a φ queues them and those of every
  // later φ of the sweep.
  const std::vector<BoxRun>& runs_for(double phi, bool& fresh) {
    std::vector<std::pair<double, BoxPool::Future>> pending;
    {
      const std::lock_guard lock(mutex_);
      if (const auto it = done_.find(phi); it != done_.end()) return it->second;
      fresh = true;
      queue(phi);
      for (const double later : volume_fractions_)
        if (later > phi) queue(later);
      pending = queued_.at(phi);
    }
    std::vector<BoxRun> runs;
    for (auto& [rate, future] : pending) runs.push_back({rate, future.get()});
    const std::lock_guard lock(mutex_);
    return done_.emplace(phi, std::move(runs)).first->second;
  }

  void queue(double phi) {  // mutex_ held
    if (queued_.contains(phi)) return;
    auto& jobs = queued_[phi];
    const auto rates = box_is_rate_independent(r_) ? std::vector<double>{0.0} : r_.shear_rates;
    for (const double rate : rates)
      jobs.emplace_back(rate, pool_.submit(box_settings(r_, phi, rate > 0.0 ? rate : r_.shear_rates.back())));
  }

  RheometerCase r_;
  std::vector<double> volume_fractions_;
  std::mutex mutex_;
  std::map<double, std::vector<std::pair<double, BoxPool::Future>>> queued_;
  std::map<double, std::vector<BoxRun>> done_;
  BoxPool pool_;  // last: its workers stop before the maps they fill go
};

}  // namespace

PointRunner make_box_suspension_runner(const RheometerCase& rheometer, std::vector<double> volume_fractions) {
  auto runner = std::make_shared<BoxRunner>(rheometer, std::move(volume_fractions));
  return [runner](const SweepPoint& point, const PointProgressCallback&) { return runner->run(point); };
}

}  // namespace rheosim::rheometer
