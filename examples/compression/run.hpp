#pragma once
// compression_specimen::run and the summary (specimen.hpp, main.cpp).

#include <array>
#include <chrono>
#include <map>

#include "tessera/io/atomic_file.hpp"
#include "tessera/io/csv.hpp"
#include "common/snapshots.hpp"

namespace tessera::scenes {

/// The mantle's gridpoints with their share of its area (m^2, one third of each surface triangle
/// on it) and outward normal: triangles whose normal is horizontal and whose plane is the
/// specimen's side at `apothem` from the axis.
struct mantle_nodes {
  std::vector<index_t> node;
  std::vector<vec3> force_direction;  ///< area share x outward unit normal (m^2)
  real area = 0;                      ///< of the triangles found (m^2)
};
[[nodiscard]] inline mantle_nodes find_mantle(const geometry::block_mesh& mesh, real apothem) {
  std::map<index_t, vec3> share;
  real found = 0;
  for (const auto& t : mesh.face_triangles) {
    const vec3 &a = mesh.gridpoints[static_cast<std::size_t>(t[0])], &b = mesh.gridpoints[static_cast<std::size_t>(t[1])],
               &c = mesh.gridpoints[static_cast<std::size_t>(t[2])];
    const vec3 n2 = (b - a).cross(c - a);  // CCW seen from outside: outward, twice the area
    const real area = 0.5 * n2.norm();
    if (!(area > 0)) continue;
    const vec3 n = n2.normalized();
    if (std::abs(n.z()) > 1e-9 || std::abs(n.dot((a + b + c) / 3) - apothem) > 1e-9 * apothem) continue;
    found += area;
    for (index_t g : t) share.try_emplace(g, vec3::Zero()).first->second += area / 3 * n;  // Eigen does not zero
  }
  mantle_nodes m;
  for (const auto& [g, f] : share) m.node.push_back(g), m.force_direction.push_back(f);
  m.area = found;
  return m;
}

template <class Law>
compression_result compression_specimen<Law>::run() const {
  using law_t = Law;
  using compression_solver = scenes::compression_solver<Law>;
  const auto start = std::chrono::steady_clock::now();
  solver_options opt;
  opt.mass_scaling_dt = o_.step_displacement / o_.rate;  // the top end moves step_displacement per step
  opt.threads = o_.common.threads;
  const zones::linear_elastic_tet::params concrete = recipe_.block_material;  // semi-rigid: 10 x the concrete's E
  compression_solver s(tess_, mesh_, concrete, contact::material_table<typename law_t::params>(law_), {}, opt);
  node_set& gp = s.gridpoints();
  const real H = o_.height, tol = 1e-9 * H, pi = std::numbers::pi;
  const auto bottom = s.gridpoints_on_plane(2, 0.0, tol), top = s.gridpoints_on_plane(2, H, tol);
  // Ends: prescribed gridpoints, or steel platens evaluated by the law (frictional, never bonded).
  std::array<std::optional<contact::rigid_platen<law_t>>, 2> platen;
  if (o_.ends == "friction") {
    auto plate = law_;
    plate.shear.c_res = 0;
    plate.shear.phi_res = law::friction_angle::from_radians(std::atan(o_.friction));
    if constexpr (has_cap) plate.compression.f_c = 1e12;  // steel on concrete: the concrete's own contacts carry the cap
    if constexpr (Law::softens_with_crushing) plate.compression.residual = 1;  // and it does not crush
    if constexpr (Law::softens_with_slip)  // never bonded: only the residual acts; phi_0 >= phi_res for validate
      if (plate.shear.phi_res.radians() > plate.shear.phi_0.radians()) plate.shear.phi_0 = plate.shear.phi_res;
    contact::platen_motion m;      // held in x and y, moved along z (set_velocity), never turning
    m.mass = 7850 * section_ * 0.02;
    m.inertia = m.mass * o_.width * o_.width / 12;
    const real half = o_.width;  // the footprint covers the end face
    platen[0].emplace(mesh_, contact::platen_geometry{vec3(0, 0, 0), vec3::UnitZ(), vec3::UnitX(), half, half, tol}, m, plate);
    platen[1].emplace(mesh_, contact::platen_geometry{vec3(0, 0, H), -vec3::UnitZ(), vec3::UnitX(), half, half, tol}, m, plate);
    for (auto& p : platen) p->attach(s);
  } else {
    const bc::components along = o_.ends == "fixed" ? bc::components::xyz : bc::components::z;
    s.fix(bottom, along);
    s.prescribe_velocity(top, vec3::Zero(), along);
    if (o_.ends == "frictionless") {  // rigid-body motion in x, y and about z: two bottom gridpoints
      const auto nearest = [&](const vec3& x) {
        index_t best = bottom.nodes.front();
        for (index_t g : bottom.nodes)
          if ((gp.reference.row(g).transpose() - x).squaredNorm() < (gp.reference.row(best).transpose() - x).squaredNorm()) best = g;
        return best;
      };
      const index_t centre = nearest(vec3::Zero()), side = nearest(vec3(0.4 * o_.width, 0, 0));
      s.fix(bc::node_group{{centre}, "centre pin"}, bc::components::xy);
      s.fix(bc::node_group{{side}, "turn pin"}, bc::components::y);
    }
  }
  // Confinement: a dead load on the mantle, registered as applied forces (stiffness 0).
  const mantle_nodes mantle = o_.confinement > 0 ? find_mantle(mesh_, apothem_) : mantle_nodes{};
  if (o_.confinement > 0) {
    require(!mantle.node.empty(), "compression: no surface triangle on the mantle");
    // The shares must add up to the mantle's area and cancel as vectors (a closed side surface).
    const real area = mantle.area;
    vec3 net = vec3::Zero();
    for (const vec3& f : mantle.force_direction) net += f;
    const real expected = o_.shape == "cylinder" ? compression_sides * o_.width * std::sin(pi / compression_sides) * H : 4 * o_.width * H;
    require(std::abs(area - expected) <= 1e-9 * expected && net.norm() <= 1e-9 * expected, "compression: the mantle's ",
            mantle.node.size(), " gridpoints carry ", area, " m^2 of surface (the side is ", expected, " m^2) with a net ",
            net.norm(), " m^2: the confinement would not be a closed pressure");

    s.register_applied_forces(std::span<const index_t>(mantle.node), std::vector<real>(mantle.node.size(), 0.0));
  }
  compression_result r;
  const auto& ms = s.mass_scaling();
  r.added_mass_ratio = ms.original_mass > 0 ? ms.added_mass / ms.original_mass : 0;
  r.dt = s.dt();
  // Quasi-static: the end's travel in one period of the first axial mode (both ends held, T = 2 H / c
  // at the scaled density) against its travel to 40 % of the expected peak (f_c cap / E x H).
  const real E = recipe_.young, c = std::sqrt(E / (recipe_.block_material.density * (1 + r.added_mass_ratio)));
  r.quasi_static_index = o_.rate * 2 * H / c / (0.4 * o_.cap / E * H);  // the prism's, too, against 35 MPa
  require(r.quasi_static_index <= 0.05, "compression: --rate ", o_.rate, " m/s with --step-displacement ",
          o_.step_displacement, " m is not quasi-static: the end moves ", r.quasi_static_index,
          " x its travel to 40 % of the peak during one period of the first axial mode (limit 0.05); use a rate <= ",
          o_.rate * 0.05 / r.quasi_static_index, " m/s or a smaller step displacement");
  // The mantle over the middle half of the height, for the lateral strain.
  std::vector<std::pair<index_t, vec3>> belt;  // gridpoint, horizontal outward unit vector
  for (index_t g = 0; g < gp.size(); ++g) {
    const vec3 x = gp.reference.row(g).transpose();
    const vec3 radial(x.x(), x.y(), 0);
    const real extent = o_.shape == "cylinder" ? radial.norm() : std::max(std::abs(x.x()), std::abs(x.y()));
    if (std::abs(x.z() - H / 2) > H / 4 || extent < apothem_ * (1 - 1e-9)) continue;
    const vec3 out = o_.shape == "cylinder" ? radial.normalized()
                                            : (std::abs(x.x()) >= std::abs(x.y()) ? vec3(x.x() > 0 ? 1 : -1, 0, 0)
                                                                                  : vec3(0, x.y() > 0 ? 1 : -1, 0));
    belt.emplace_back(g, out);
  }
  require(!belt.empty(), "compression: no gridpoint on the mantle's middle half");
  soa3& applied = s.applied_forces();
  real load_factor = 0;  // the confinement's share in force
  const auto before_step = [&](compression_solver& m) {
    for (std::size_t k = 0; k < mantle.node.size(); ++k) applied.row(mantle.node[k]).setZero();
    for (auto& p : platen) if (p) p->update(m);
    for (std::size_t k = 0; k < mantle.node.size(); ++k)
      applied.row(mantle.node[k]) -= (load_factor * o_.confinement * mantle.force_direction[k]).transpose();
  };
  const auto axial_load = [&](const compression_solver& m) {  // N, compression positive
    return platen[1] ? platen[1]->force().z() : -recorders::reaction_sum(m.gridpoints(), top).z();
  };
  const auto end_travel = [&](const compression_solver& m) {  // m, shortening positive
    if (platen[1]) return -(platen[1]->displacement().z() - platen[0]->displacement().z());
    real u = 0;
    for (index_t g : top.nodes) u -= m.gridpoints().displacement(g, 2);
    return u / static_cast<real>(top.nodes.size());
  };
  const auto lateral = [&](const compression_solver& m) {
    real u = 0;
    for (const auto& [g, out] : belt) u += m.gridpoints().displacement.row(g).dot(out.transpose());
    return u / static_cast<real>(belt.size()) / apothem_;
  };
  before_step(s);
  // 1. Confinement ramped in over 20 000 steps and held 10 000 more, the ends at rest.
  if (o_.confinement > 0) {
    const std::int64_t ramp = 20000, hold = 10000;
    s.run(ramp + hold, [&](const compression_solver& m) {  // observers see the solver const: update s itself
      load_factor = std::min<real>(1, static_cast<real>(m.step_count()) / ramp);
      load_factor = 0.5 * (1 - std::cos(pi * load_factor));
      before_step(s);
    });
  }
  const real travel0 = end_travel(s), lateral0 = lateral(s);
  r.confinement_stress = axial_load(s) / section_;
  // 2. Axial loading at the rate, sampled every 1e-6 of strain.
  if (platen[1]) platen[1]->set_velocity(vec3(0, 0, -o_.rate));
  else bc::update_velocity(gp, top, vec3(0, 0, -o_.rate), o_.ends == "fixed" ? bc::components::xyz : bc::components::z);
  const auto every = static_cast<index_t>(std::max<real>(1, std::round(1e-6 * H / o_.step_displacement)));
  real largest = 0;
  bool done = false;
  const std::filesystem::path dir(o_.common.out);
  bar_snapshots snapshots(dir, mesh_, "compression.pvd", !o_.no_vtk);  // zones and contacts (no bars)
  std::optional<cli::progress_line> progress;
  if (!o_.common.quick) progress.emplace("compression");
  io::ensure_directory(dir);
  const std::int64_t max_steps = static_cast<std::int64_t>(1.5 * o_.max_strain * H / o_.step_displacement) + 10;
  const auto run = s.run_until([&](const compression_solver&) { return done; }, max_steps,
      [&](const compression_solver&) { before_step(s); },
      recorders::every(every, [&](const compression_solver& m) {
        const real eps = (end_travel(m) - travel0) / H, sigma = axial_load(m) / section_;
        r.strain.push_back(eps), r.stress.push_back(sigma), r.lateral_strain.push_back(lateral(m) - lateral0);
        if (sigma > largest && !r.peak) largest = sigma, r.peak_stress = sigma, r.peak_strain = eps, r.lateral_at_peak = r.lateral_strain.back();
        if (!r.peak && eps > 2e-4 && sigma <= (1 - o_.drop) * largest) r.peak = true;
        done = r.peak || eps >= o_.max_strain;
        if (progress) progress->update(std::min(1.0, eps / o_.max_strain), tessera::detail::concat("strain ", eps, ", ", sigma * 1e-6, " MPa"));
      }));
  if (progress) progress->finish();
  r.steps = s.step_count();
  r.damping = s.damping_in_force();
  r.stop_reason = run.hit_max_steps ? run.reason : (r.peak ? "post-peak drop" : "max strain");
  r.last_strain = r.strain.empty() ? 0 : r.strain.back();
  r.residual_ratio = largest > 0 && !r.stress.empty() ? r.stress.back() / largest : 0;
  compression_moduli(r);
  const auto& cs = s.contacts();
  real axial = 0;
  for (index_t i = 0; i < cs.size(); ++i)
    if (law_t::tensile_damage(cs.subcontact_params(i), cs.state(i)) >= 0.5 ||
        law::has(law_t::status(cs.state(i)), law::contact_status::slipped)) {
      r.cracked_area += cs.area(i);
      if (std::abs(cs.normal(i).z()) < 0.5) axial += cs.area(i);  // normal within 30 deg of horizontal
    }
  r.axial_crack_share = r.cracked_area > 0 ? axial / r.cracked_area : 0;
  r.energy_error_rel = s.energies().error_rel();
  snapshots(s, "end");
  io::write_csv(dir / "curve.csv", {"axial_strain", "axial_stress_Pa", "lateral_strain"}, {r.strain, r.stress, r.lateral_strain});
  r.runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

/// The mode-II fracture energy G_II (J/m^2) of contact parameters p; NaN (null) for a law without one.
template <class Params>
[[nodiscard]] real slip_energy(const Params& p) {
  if constexpr (requires { p.shear.G_II; }) return p.shear.G_II;
  else return std::numeric_limits<real>::quiet_NaN();
}

/// The softening cap's G_c (J/m^2), residual fraction and shear coupling (1 or 0) of contact
/// parameters p; NaN (null) for a law whose cap does not soften.
template <class Params>
[[nodiscard]] std::array<real, 3> crush_parameters(const Params& p) {
  if constexpr (requires { p.compression.G_c; })
    return {p.compression.G_c, p.compression.residual, p.compression.scales_shear ? 1.0 : 0.0};
  else return {std::numeric_limits<real>::quiet_NaN(), std::numeric_limits<real>::quiet_NaN(), std::numeric_limits<real>::quiet_NaN()};
}

/// summary.json of a compression run.
template <class Law>
void write_compression_summary(io::summary_json& j, const compression_options& o, const compression_specimen<Law>& sp,
                               const compression_result& r) {
  const auto& p = sp.contact_params();
  const real none = std::numeric_limits<real>::quiet_NaN();  // null: a run without a peak has no f_c, the prism no cap
  real cap = none;
  if constexpr (compression_specimen<Law>::has_cap) cap = p.compression.f_c;
  j.set("example", "compression").set("material", o.material).set("quick", o.common.quick).set("seed", static_cast<std::int64_t>(o.common.seed))
      .set("shape", o.shape).set("diameter_m", o.width).set("height_m", o.height).set("blocks", static_cast<std::int64_t>(sp.block_count()))
      .set("zones", static_cast<std::int64_t>(sp.zone_count())).set("zone_edge_m", sp.zone_edge()).set("ends", o.ends)
      .set("friction", o.ends == "friction" ? o.friction : 0.0).set("confinement_Pa", o.confinement)
      .set("k_n_Pa_per_m", p.k_n).set("k_s_Pa_per_m", p.k_s).set("f_T_Pa", p.tension.f_T).set("c_0_Pa", p.shear.c_0)
      .set("law", o.law).set("G_II_J_per_m2", slip_energy(p)).set("G_c_J_per_m2", crush_parameters(p)[0])
      .set("cap_residual", crush_parameters(p)[1]).set("crush_shear", crush_parameters(p)[2])
      .set("phi_0_deg", o.phi_deg).set("phi_res_deg", o.phi_res_deg).set("cap_Pa", cap).set("G_f_N_per_m", p.tension.G_f)
      .set("rate_m_per_s", o.rate).set("step_displacement_m", o.step_displacement).set("dt_s", r.dt).set("damping_in_force", r.damping)
      .set("added_mass_ratio", r.added_mass_ratio).set("quasi_static_index", r.quasi_static_index)
      .set("peak", r.peak).set("stop_reason", r.stop_reason)
      .set("largest_stress_Pa", r.peak_stress).set("strain_at_largest", r.peak_strain).set("last_strain", r.last_strain)
      .set("residual_over_largest", r.residual_ratio).set("confinement_axial_stress_Pa", r.confinement_stress)
      .set("young_Pa", r.young).set("poisson", r.poisson).set("lateral_strain_at_largest", r.lateral_at_peak)
      .set("reference_f_c_Pa", 35e6).set("reference_peak_strain", 2e-3)
      .set("cracked_area_m2", r.cracked_area).set("axial_crack_share", r.axial_crack_share)
      .set("energy_balance_error_rel", r.energy_error_rel).set("steps", r.steps).set("threads", max_threads())
      .set("runtime_s", r.runtime_s);
  j.set("f_c_Pa", r.peak ? r.peak_stress : none).set("peak_strain", r.peak ? r.peak_strain : none)
      .set("f_c_over_reference", r.peak ? r.peak_stress / 35e6 : none);
}

}  // namespace tessera::scenes
