#pragma once
// Hertz contact scales for elastic spheres, used to choose the DEM time step (a fraction
// of the Rayleigh time) and to check the contact parameters handed to
// LIGGGHTS' `model hertz`. SI throughout.
//
// Effective properties of a contact between spheres a and b (Hertz; Johnson, Contact
// Mechanics, 1985, §4.2):
//   1/E* = (1 − ν_a²)/E_a + (1 − ν_b²)/E_b      like spheres: E* = E/(2(1 − ν²))
//   1/r* = 1/r_a + 1/r_b                          like spheres: r* = r/2
//   1/m* = 1/m_a + 1/m_b                          like spheres: m* = m/2
// LIGGGHTS' `model hertz` uses the same Y_eff and r_eff (normal_model_hertz.h).
//
// Rayleigh time: the time a Rayleigh surface wave takes to cross a sphere, the usual bound
// for the DEM step in LIGGGHTS (fix check/timestep/gran) and EDEM:
//   t_R = π r √(ρ/G) / (0.1631 ν + 0.8766),   G = E/(2(1 + ν))
// The denominator is a linear fit of the Rayleigh-wave speed ratio c_R/c_S for 0 <= ν <= 0.5.
// Common practice is Δt = 0.1–0.4 t_R (fraction 0.2 is the default here). The CD seed §4
// particles (r = 100 µm, ρ = 1000 kg/m³, E = 3 GPa, ν = 0.33) give t_R = 3.18e-7 s; the seed's
// DEM step of 1e-7 s is 0.31 t_R.
//
// Hertz collision duration of a head-on impact at relative speed v (Johnson 1985, eq. 11.24;
// the "Hertz time" of fix check/timestep/gran):
//   t_c = 2.87 (m*² / (r* E*² v))^(1/5)
// t_c ∝ v^(−1/5) and, for like spheres at fixed v, ∝ r.
//
// Damping from the coefficient of restitution e, as in LIGGGHTS' `model hertz` (Tsuji et al.,
// Powder Technol. 71 (1992) 239; Antypov & Elliott, EPL 94 (2011) 50004):
//   β = ln e / √(ln² e + π²)                        (<= 0; 0 for e = 1)
//   γ_n = −2 √(5/6) β √(S_n m*),   S_n = 2 E* √(r* δ_n)
// with normal overlap δ_n; the damping force is −γ_n v_n.
namespace rheosim::dem {

// Material and size of one elastic sphere.
struct ElasticSphere {
  double radius = 0.0;          // r [m], > 0
  double density = 0.0;         // ρ [kg/m³], > 0
  double youngs_modulus = 0.0;  // E [Pa], > 0
  double poisson_ratio = 0.0;   // ν [-], in [0, 0.5]
};

// Throws std::invalid_argument naming the field and its valid range.
void check(const ElasticSphere& sphere);

[[nodiscard]] double mass(const ElasticSphere& sphere);                                  // m = ρ π d³/6 [kg]
[[nodiscard]] double shear_modulus(double youngs_modulus, double poisson_ratio);         // G [Pa]
[[nodiscard]] double effective_modulus(const ElasticSphere& a, const ElasticSphere& b);  // E* [Pa]
[[nodiscard]] double effective_radius(const ElasticSphere& a, const ElasticSphere& b);   // r* [m]
[[nodiscard]] double effective_mass(const ElasticSphere& a, const ElasticSphere& b);     // m* [kg]

// t_R [s] of one sphere.
[[nodiscard]] double rayleigh_time(const ElasticSphere& sphere);
// fraction · t_R [s]; fraction in (0, 1].
[[nodiscard]] double rayleigh_time_step(const ElasticSphere& sphere, double fraction = 0.2);

// t_c [s] for spheres a and b meeting at relative normal speed impact_speed > 0 [m/s].
[[nodiscard]] double hertz_collision_time(const ElasticSphere& a, const ElasticSphere& b, double impact_speed);

// β [-] from the coefficient of restitution e in (0, 1].
[[nodiscard]] double damping_ratio_from_restitution(double restitution);
// γ_n [kg/s] of LIGGGHTS' model hertz at normal overlap δ_n >= 0 [m].
[[nodiscard]] double hertz_normal_damping(const ElasticSphere& a, const ElasticSphere& b, double restitution,
                                          double overlap);

}  // namespace rheosim::dem
