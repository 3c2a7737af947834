// η_r(φ), N1, N2 of the Lees–Edwards suspension box against the measured band, with its cost:
// one line per φ (docs/suspension-box.md). Every setting is a command-line option.
//   bench_suspension_box --phi 0.1,0.2,0.3,0.4,0.5 [--particles 500] [--friction 0.3]
//                        [--stokes 0] [--stiffness 0] [--strain 40] [--seed 1] [--size-ratio 1]
//                        [--wall-gap 0,2.5,5,10] (H/d of a walled box; 0 the bulk box)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "rheosim/coupling/suspension_box.hpp"
#include "rheosim/rheometer/analysis.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Lees–Edwards suspension box: η_r(φ), N1, N2 and cost"};
  std::vector<double> phis{0.1, 0.2, 0.3, 0.4, 0.5};
  rheosim::coupling::SuspensionBoxSettings s;
  double size_ratio = 1.0;
  double bingham = 0.0;
  app.add_option("--phi", phis, "volume fractions")->delimiter(',');
  app.add_option("--particles", s.particles, "spheres in the box");
  app.add_option("--friction", s.friction, "Coulomb friction coefficient");
  app.add_option("--stokes", s.stokes_number, "St = m γ̇/(6πμa); 0 overdamped");
  app.add_option("--stiffness", s.contact_stiffness, "k_n/(6πμaγ̇); 0 = default for φ");
  app.add_option("--strain-step", s.strain_step, "Δγ; 0 = default");
  app.add_option("--strain", s.max_strain, "maximum strain");
  app.add_option("--min-strain", s.min_averaging_strain, "minimum averaging strain");
  app.add_option("--warmup", s.warmup_strain, "strain left out of the averages");
  app.add_option("--block", s.block_strain, "averaging block length (strain)");
  app.add_option("--tolerance", s.relative_tolerance, "relative standard error to stop at");
  app.add_option("--roughness", s.roughness, "δ/ā");
  app.add_option("--cutoff", s.lubrication_cutoff, "h_c/ā");
  app.add_option("--repulsion", s.repulsion_force, "F_R0/(6πμa²γ̇)");
  app.add_option("--seed", s.seed, "placement seed");
  app.add_option("--solver-tolerance", s.solver_tolerance, "relative residual of the implicit solve");
  app.add_option("--size-ratio", size_ratio, "bidisperse large/small radius at equal volumes (1: monodisperse)");
  std::vector<double> wall_gaps{0.0};
  app.add_option("--wall-gap", wall_gaps,
                 "plate gaps H/d (diameters of the reference sphere), comma separated; 0: Lees–Edwards bulk box")
      ->delimiter(',');
  bool linear_flow = false;
  app.add_flag("--linear-flow", linear_flow,
               "walled box: keep the liquid's linear profile u∞ (one-way) instead of its mean-flow solution");
  app.add_option("--bingham", bingham,
                 "Bingham matrix at this Bingham number τ_y/(μ_p γ̇) (0: Newtonian); η_r is then relative to the "
                 "secant viscosity, and the plastic limit of η_r is τ_y,s/τ_y (Chateau, Ovarlez & Trung 2008)");
  CLI11_PARSE(app, argc, argv);
  if (size_ratio != 1.0) {
    s.radii = {1.0, size_ratio};
    s.volume_shares = {0.5, 0.5};
  }
  if (bingham > 0.0) {
    // μ(sγ̇)/μ(γ̇) = (1 + Bn/s)/(1 + Bn); homogenised stresslet μ_S/μ = 0.3 + 0.7 μ_p/μ(γ̇).
    s.viscosity_ratio = [bingham](double ratio) { return (1.0 + bingham / ratio) / (1.0 + bingham); };
    s.stresslet_viscosity_ratio = 0.3 + 0.7 / (1.0 + bingham);
  }
  std::printf("# Bingham number %g (0: Newtonian matrix)\n", bingham);
  std::printf("# particles %d, friction %g, St %g, roughness %g, cutoff %g, repulsion %g, size ratio %g\n", s.particles,
              s.friction, s.stokes_number, s.roughness, s.lubrication_cutoff, s.repulsion_force, size_ratio);
  std::printf("%6s %6s %8s %7s %7s %7s %7s %7s %7s %7s %7s %7s %7s %7s %7s %7s %6s %6s %7s %7s %8s\n", "phi", "H/d",
              "eta_r", "err", "KD.63", "Boyer", "Zarraga", "lub", "contact", "N1/tau", "+-", "N2/tau", "+-", "Pi/tau",
              "z", "slide", "ovl", "ovlmax", "strain", "iters", "seconds");
  std::printf("# H/d = 0: Lees–Edwards bulk box; otherwise walled, and slip is the near-plate lag [a gamma_dot]\n");
  for (const double gap : wall_gaps)
    for (const double phi : phis) {
      s.volume_fraction = phi;
      s.wall_gap = 2.0 * gap;  // H/a
      s.mean_flow_coupling = !linear_flow;
      const auto r = rheosim::coupling::run_suspension_box(s);
      const double eta = r.relative_viscosity.mean;
      std::printf(
          "%6.3f %6.2f %8.4f %7.4f %7.3f %7.3f %7.3f %7.3f %7.3f %7.3f %6.3f %7.3f %6.3f %7.3f %7.2f %7.3f %6.4f %6.4f "
          "%7.1f %7.1f %8.2f\n",
          phi, gap, eta, r.relative_viscosity.error,
          rheosim::rheometer::krieger_dougherty_relative_viscosity(phi, 0.63),
          rheosim::rheometer::boyer_relative_viscosity(phi), rheosim::rheometer::zarraga_relative_viscosity(phi),
          r.part_lubrication, r.part_contact, r.n1.mean / eta, r.n1.error / eta, r.n2.mean / eta, r.n2.error / eta,
          r.particle_pressure.mean / eta, r.mean_contacts_per_particle, r.sliding_fraction, r.mean_overlap,
          r.max_overlap, r.strain, r.mean_solver_iterations, r.wall_time);
      if (gap > 0.0)
        std::printf(
            "#   walled box %.3g x %.3g x %.3g a, %s, wall slip %.4f a gamma_dot, liquid shear rate core %.4f / "
            "plates %.4f gamma_dot\n",
            r.box_length, r.box_length, r.box_height, linear_flow ? "linear liquid profile" : "mean-flow liquid",
            r.wall_slip, r.core_shear_rate, r.plate_shear_rate);
      for (const auto& w : r.warnings) std::printf("#   warning: %s\n", w.c_str());
      std::fflush(stdout);
    }
}
