// The module's bindings of the scene's parts (bind_scene.hpp): errors, geometry, laws and their
// presets, block and contact parameters, solver options, gridpoints and results as NumPy views,
// supports' components, per-sub-contact state and energies. No solver type is named here, so this
// translation unit parses no solver (tessera_module.cpp binds those).
#include "bind_scene.hpp"

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <tessera/blocks.hpp>
#include <tessera/contact.hpp>
#include <tessera/geometry.hpp>
#include <tessera/law.hpp>
#include <tessera/presets/pulatsu2020.hpp>  // the study's presets (study_prism_params, ...)
#include <tessera/solver.hpp>

#include "bind_table.hpp"  // bind_material_table
#include "contact_state.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace py = pybind11;

namespace tessera::python {

namespace {

/// A read-only NumPy view (n x 3, no copy) of a column-major soa3 owned by `owner`.
py::array view_of(const soa3& a, py::handle owner) {
  const auto n = static_cast<py::ssize_t>(a.rows());
  const auto item = static_cast<py::ssize_t>(sizeof(real));
  py::array v(py::dtype::of<real>(), {n, py::ssize_t{3}}, {item, n * item}, a.data(), owner);
  py::detail::array_proxy(v.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return v;
}
/// A read-only NumPy view (n, no copy) of an Eigen vector owned by `owner`.
py::array view_of(const Eigen::VectorXd& a, py::handle owner) {
  py::array v(py::dtype::of<real>(), {static_cast<py::ssize_t>(a.size())}, {static_cast<py::ssize_t>(sizeof(real))},
              a.data(), owner);
  py::detail::array_proxy(v.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return v;
}
/// A NumPy copy (n) of a vector of numbers, one copy of the memory (no Python objects between).
template <class T>
py::array array_of(const std::vector<T>& v) {
  py::array_t<T> out(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), out.mutable_data());
  return out;
}
/// A NumPy copy (n x 3) of a list of 3-vectors.
py::array rows_of(const std::vector<vec3>& v) {
  py::array_t<double> out({static_cast<py::ssize_t>(v.size()), py::ssize_t{3}});
  auto w = out.mutable_unchecked<2>();
  for (std::size_t k = 0; k < v.size(); ++k)
    for (py::ssize_t d = 0; d < 3; ++d) w(static_cast<py::ssize_t>(k), d) = v[k][d];
  return out;
}
/// The fields every detected_contacts<Law>::params shares (tolerance, rebuild interval, initial
/// overlap), bound on its class.
template <class P>
void bind_detected_fields(py::class_<P>& cls) {
  cls.def_readwrite("tolerance", &P::tolerance, "contact tolerance (m)")
      .def_readwrite("max_rebuild_interval", &P::max_rebuild_interval, "steps between rebuilds")
      .def_readwrite("allow_initial_overlap", &P::allow_initial_overlap,
                     "accept overlaps within the tolerance at the start");
}

}  // namespace

void bind_scene(py::module_& m) {
  // ---- errors: tessera::error and its kinds as Python exceptions (base first) ----
  static py::exception<tessera::error> error(m, "Error", PyExc_RuntimeError);
  static py::exception<tessera::invalid_input> invalid(m, "InvalidInput", error.ptr());
  static py::exception<tessera::geometry_error> geometry_err(m, "GeometryError", error.ptr());
  static py::exception<tessera::io_error> io_err(m, "IoError", error.ptr());
  static py::exception<tessera::numerical_instability> unstable(m, "NumericalInstability", error.ptr());
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const tessera::invalid_input& e) {
      invalid(e.what());
    } catch (const tessera::geometry_error& e) {
      geometry_err(e.what());
    } catch (const tessera::io_error& e) {
      io_err(e.what());
    } catch (const tessera::numerical_instability& e) {
      unstable(e.what());
    } catch (const tessera::error& e) {
      error(e.what());
    }
  });

  // ---- geometry ----
  auto g = m.def_submodule("geometry", "Convex blocks, tessellations and their zoning (m)");
  py::class_<geometry::convex_polyhedron>(g, "convex_polyhedron", "A convex polyhedron (m)")
      .def_static("box", &geometry::convex_polyhedron::box, py::arg("lo"), py::arg("hi"),
                  "The axis-aligned box between corners lo and hi (m)")
      .def("volume", &geometry::convex_polyhedron::volume, "Volume (m^3)")
      .def("centroid", &geometry::convex_polyhedron::centroid, "Centroid (m)");
  g.def("voussoir", &geometry::voussoir, py::arg("center"), py::arg("r_in"), py::arg("r_out"), py::arg("theta_0"),
        py::arg("theta_1"), py::arg("depth"),
        "An arch block between radii r_in and r_out (m) and angles theta_0 < theta_1 (rad) about center, depth deep (m)");
  py::class_<geometry::tessellation>(g, "tessellation", "Cells with their shared faces")
      .def("cell_count", &geometry::tessellation::cell_count, "Number of cells (blocks)")
      .def("face_count", &geometry::tessellation::face_count, "Number of faces")
      .def("vertex_count", &geometry::tessellation::vertex_count, "Number of vertices");
  g.def(
      "separate_blocks",
      [](const std::vector<geometry::convex_polyhedron>& blocks) { return geometry::separate_blocks(blocks); },
      py::arg("blocks"), "A tessellation of separate blocks: cell b is blocks[b]");
  py::class_<geometry::block_mesh>(g, "block_mesh", "The tessellation's blocks zoned into gridpoints and zones")
      .def("block_count", &geometry::block_mesh::block_count, "Number of blocks")
      .def("gridpoint_count", &geometry::block_mesh::gridpoint_count, "Number of gridpoints")
      .def("zone_count", &geometry::block_mesh::zone_count, "Number of zones");
  g.def(
      "zone_blocks", [](const geometry::tessellation& t) { return geometry::zone_blocks(t); }, py::arg("tess"),
      "Zones every block of tess (default zoning options)");

  // ---- laws ----
  auto l = m.def_submodule("law", "Contact laws (Pa/m, Pa, deg)");
  py::class_<law::friction_angle>(l, "friction_angle", "A friction angle")
      .def_static("from_degrees", &law::friction_angle::from_degrees, py::arg("phi_deg"), "An angle in degrees")
      .def_static("from_radians", &law::friction_angle::from_radians, py::arg("phi"), "An angle in radians")
      .def("degrees", &law::friction_angle::degrees, "phi (deg)")
      .def("radians", &law::friction_angle::radians, "phi (rad)");
  py::class_<law::dry_joint_law::params>(l, "dry_joint_params", "The params of a dry frictional joint")
      .def_readonly("k_n", &law::dry_joint_law::params::k_n, "normal stiffness (Pa/m)")
      .def_readonly("k_s", &law::dry_joint_law::params::k_s, "shear stiffness (Pa/m)");
  l.def("dry_joint", &law::dry_joint, py::arg("k_n"), py::arg("k_s"), py::arg("phi"),
        "A dry frictional joint: k_n, k_s (Pa/m, > 0), friction angle phi in [0, 90) deg");
  using bonded = law::bonded_joint_law::params;
  py::class_<bonded>(l, "bonded_joint_params", "The params of a bonded cohesive joint (law::bonded_joint_law)")
      .def_readonly("k_n", &bonded::k_n, "normal stiffness (Pa/m)")
      .def_readonly("k_s", &bonded::k_s, "shear stiffness (Pa/m)")
      .def_property_readonly("tensile_strength", [](const bonded& p) { return p.tension.f_T; }, "f_T (Pa)")
      .def_property_readonly("fracture_energy", [](const bonded& p) { return p.tension.G_f; }, "G_f (N/m)")
      .def_property_readonly("cohesion", [](const bonded& p) { return p.shear.c_0; }, "c_0 (Pa)")
      .def_property_readonly("residual_cohesion", [](const bonded& p) { return p.shear.c_res; }, "c_res (Pa)");
  l.def(
      "bonded_joint",
      [](real k_n, real k_s, real f_t, real g_f, real c_0, const law::friction_angle& phi_0, real c_res,
         const law::friction_angle& phi_res) {
        return law::bonded_joint({.k_n = k_n, .k_s = k_s, .tensile_strength = f_t, .fracture_energy = g_f,
                                  .cohesion = c_0, .friction = phi_0, .residual_cohesion = c_res,
                                  .residual_friction = phi_res});
      },
      py::kw_only(), py::arg("k_n"), py::arg("k_s"), py::arg("tensile_strength"), py::arg("fracture_energy"),
      py::arg("cohesion"), py::arg("friction"), py::arg("residual_cohesion"), py::arg("residual_friction"),
      "A bonded cohesive joint (law::bonded_joint), every value named: k_n, k_s (Pa/m, > 0), tensile_strength f_T "
      "(Pa, > 0) softening linearly over fracture_energy G_f (N/m, > f_T^2 / (2 k_n)), cohesion c_0 (Pa) and "
      "friction phi_0 while intact, residual_cohesion c_res (Pa, [0, c_0]) and residual_friction phi_res once "
      "broken or slipped (friction angles: law.friction_angle)");

  // ---- blocks and contacts ----
  auto b = m.def_submodule("blocks", "Block models");
  py::class_<blocks::rigid> rigid(b, "rigid", "Rigid blocks (the model of a solver)");
  rigid.def("weight_mass", &blocks::rigid::weight_mass, py::arg("b"), "The mass gravity acts on (kg) of block b");
  py::class_<blocks::rigid::params>(rigid, "params", "A rigid block material")
      .def(py::init<real>(), py::arg("density"), "density (kg/m^3)")
      .def_readwrite("density", &blocks::rigid::params::density, "density (kg/m^3)");
  auto c = m.def_submodule("contact", "Contact sets");
  using dry_contacts = contact::detected_contacts<law::dry_joint_law>;
  py::class_<dry_contacts::params> dry(c, "detected_dry_joints",
                                       "contact::detected_contacts<law::dry_joint_law>::params: a dry joint law and "
                                       "the contact tolerance (m)");
  bind_detected_fields(dry);
  dry.def(py::init([](const law::dry_joint_law::params& p, real tol) { return dry_contacts::params(p, tol); }),
          py::arg("law"), py::arg("tolerance"))
      .def_readwrite("deformable_blocks", &dry_contacts::params::deformable_blocks,
                     "True for deformable blocks (instances.deformable_dry_solver and its damped twin): the "
                     "sub-contacts sit on surface gridpoints; False (default) for rigid blocks");
  using bonded_contacts = contact::detected_contacts<law::bonded_joint_law>;
  py::class_<bonded_contacts::params> bonded_joints(
      c, "detected_bonded_joints",
      "contact::detected_contacts<law::bonded_joint_law>::params: a bonded joint law, the contact tolerance (m) and "
      "whether the faces the blocks start on are bonded");
  bind_detected_fields(bonded_joints);
  bonded_joints
      .def(py::init([](const law::bonded_joint_law::params& p, real tol, bool bond_faces) {
             return bonded_contacts::params(p, tol, 1000, bond_faces);
           }),
           py::arg("law"), py::arg("tolerance"), py::arg("bond_faces") = false)
      .def_readwrite("bond_faces", &bonded_contacts::params::bond_faces,
                     "True: the corners of faces that coincide at the start (gap within 1e-3 x tolerance, as "
                     "separate_blocks' neighbours) start intact with f_T, c_0, phi_0; False (default): every "
                     "contact starts unbonded on c_res, phi_res");
  py::class_<reinforcement::none::params>(m, "no_reinforcement", "The params of reinforcement::none").def(py::init<>());

  // ---- solver options, state, results ----
  py::class_<solver_options>(m, "solver_options", "Run-time options of a solver (SI)")
      .def(py::init<>())
      .def_readwrite("safety", &solver_options::safety, "dt = safety x the critical step, in (0, 1]")
      .def_readwrite("dt", &solver_options::dt, "user time step (s); 0 = automatic")
      .def_readwrite("mass_scaling_dt", &solver_options::mass_scaling_dt,
                     "> 0: nodal masses raised so this step (s) is stable, and used")
      .def_readwrite("mass_scaling_ratio", &solver_options::mass_scaling_ratio,
                     "> 0 (instead of mass_scaling_dt): masses scaled to the step at which the added mass is this "
                     "multiple of the model's mass (-)")
      .def_readwrite("damping_gamma", &solver_options::damping_gamma, "local damping constant")
      .def_readwrite("threads", &solver_options::threads, "OpenMP threads; 0 = leave the current setting")
      .def_readwrite("check_interval", &solver_options::check_interval, "steps between step-checker passes");
  py::class_<bc::node_group>(m, "node_group", "A named group of gridpoints")
      .def_readonly("nodes", &bc::node_group::nodes, "node indices, increasing")
      .def_readonly("name", &bc::node_group::name, "the selection's name")
      .def("__len__", &bc::node_group::size);
  py::class_<node_set>(m, "node_set", "Gridpoints: read-only NumPy views (n x 3, SI), valid until the next step")
      .def("size", &node_set::size, "Number of nodes")
      .def_property_readonly("reference", [](py::object self) { return view_of(self.cast<const node_set&>().reference, self); }, "reference positions X (m)")
      .def_property_readonly("displacement", [](py::object self) { return view_of(self.cast<const node_set&>().displacement, self); }, "displacements u (m)")
      .def_property_readonly("velocity", [](py::object self) { return view_of(self.cast<const node_set&>().velocity, self); }, "velocities, half step (m/s)")
      .def_property_readonly("reaction", [](py::object self) { return view_of(self.cast<const node_set&>().reaction, self); }, "support reactions, last step (N)")
      .def_property_readonly("mass", [](py::object self) { return view_of(self.cast<const node_set&>().mass, self); }, "lumped masses (kg)");
  py::class_<run_result>(m, "run_result", "What run_until did")
      .def_readonly("steps", &run_result::steps, "steps taken by this call")
      .def_readonly("reason", &run_result::reason, "why it stopped")
      .def_readonly("hit_max_steps", &run_result::hit_max_steps, "true when max_steps ran out first")
      .def("__int__", [](const run_result& r) { return r.steps; });
  auto rec = m.def_submodule("recorders", "Sums and means over node groups");
  rec.def("reaction_sum", &recorders::reaction_sum, py::arg("nodes"), py::arg("group"),
          "Sum of the support reactions on the group (N, NumPy 3-vector)");
  rec.def("mean_displacement", &recorders::mean_displacement, py::arg("nodes"), py::arg("group"),
          "Mean displacement of the group (m, NumPy 3-vector)");

  // ---- supports: components, selections ----
  auto bcm = m.def_submodule("bc", "Boundary conditions: the components a support or velocity acts on");
  py::enum_<bc::components>(bcm, "components", "Velocity components a support acts on")
      .value("none", bc::components::none)
      .value("x", bc::components::x)
      .value("y", bc::components::y)
      .value("z", bc::components::z)
      .value("xy", bc::components::xy)
      .value("xz", bc::components::xz)
      .value("yz", bc::components::yz)
      .value("xyz", bc::components::xyz)
      .def("__or__", [](bc::components a, bc::components o) { return a | o; });
  bcm.def(
      "transverse_to",
      [](int axis) {
        require(axis >= 0 && axis <= 2, "bc::transverse_to: axis = ", axis, " must be 0, 1 or 2");
        return bc::transverse_to(axis);
      },
      py::arg("axis"), "The two components transverse to axis (0 x, 1 y, 2 z)");
  bcm.def(
      "along",
      [](int axis) {
        require(axis >= 0 && axis <= 2, "bc::along: axis = ", axis, " must be 0, 1 or 2");
        return bc::along(axis);
      },
      py::arg("axis"), "The single component of axis (0 x, 1 y, 2 z)");

  // ---- deformable blocks and the study's bonded joints (the prism) ----
  auto zn = m.def_submodule("zones", "Zone (tetrahedron) models of deformable blocks");
  py::class_<zones::linear_elastic_tet> tet(zn, "linear_elastic_tet", "Linear elastic constant-strain tetrahedra");
  py::class_<zones::linear_elastic_tet::params>(tet, "params", "An elastic block material (Pa, -, kg/m^3)")
      .def(py::init([](real young, real poisson, real density) {
             zones::linear_elastic_tet::params p{young, poisson, density};
             zones::linear_elastic_tet::validate(p);
             return p;
           }),
           py::arg("young"), py::arg("poisson"), py::arg("density"),
           "Young's modulus E (Pa, > 0), Poisson's ratio nu in (-1, 0.5), density (kg/m^3, > 0)")
      .def_readwrite("young", &zones::linear_elastic_tet::params::young, "E (Pa)")
      .def_readwrite("poisson", &zones::linear_elastic_tet::params::poisson, "nu (-)")
      .def_readwrite("density", &zones::linear_elastic_tet::params::density, "rho (kg/m^3)");

  using tie = presets::study_tie_law;  // instances::prism_law, the prism solver's
  py::class_<tie> tie_law(l, "study_tie_law",
                          "The study's bonded joint: power softening in tension, elastic compression, Coulomb "
                          "friction with residual values (law::cohesive_frictional)");
  py::class_<law::power_softening::params>(l, "power_softening_params", "Tension: power softening (Pa, J/m^2)")
      .def(py::init<>())
      .def_readwrite("f_T", &law::power_softening::params::f_T, "tensile strength (Pa)")
      .def_readwrite("G_f", &law::power_softening::params::G_f, "fracture energy (J/m^2)")
      .def_readwrite("alpha", &law::power_softening::params::alpha, "softening exponent (> 1)")
      .def_readwrite("residual_ratio", &law::power_softening::params::residual_ratio, "broken once f_t <= this x f_T");
  py::class_<law::coulomb_residual::params>(l, "coulomb_residual_params", "Shear: Coulomb with residual values (Pa)")
      .def(py::init<>())
      .def_readwrite("c_0", &law::coulomb_residual::params::c_0, "initial cohesion (Pa)")
      .def_readwrite("phi_0", &law::coulomb_residual::params::phi_0, "initial friction angle")
      .def_readwrite("c_res", &law::coulomb_residual::params::c_res, "residual cohesion (Pa)")
      .def_readwrite("phi_res", &law::coulomb_residual::params::phi_res, "residual friction angle")
      .def_readwrite("slip_breaks_tension", &law::coulomb_residual::params::slip_breaks_tension,
                     "a contact failed in shear is broken in tension too");
  py::class_<tie::params>(tie_law, "params", "The params of the study's bonded joint (Pa/m, Pa, J/m^2)")
      .def(py::init<>())
      .def_readwrite("k_n", &tie::params::k_n, "normal stiffness (Pa/m)")
      .def_readwrite("k_s", &tie::params::k_s, "shear stiffness (Pa/m)")
      .def_readwrite("tension", &tie::params::tension, "power softening: f_T (Pa), G_f (J/m^2), alpha")
      .def_readwrite("shear", &tie::params::shear, "Coulomb: c_0, phi_0, c_res, phi_res")
      .def("validate", [](const tie::params& p) { tie::validate(p); }, "Refuses bad values (tessera.Error naming one)");
  l.def("study_prism_params", &presets::study_prism_params, py::arg("blocks"),
        "The study's Table 1 prism contacts for 100, 250, 500 or 750 blocks (law::study_prism_params)");
  l.def("scaled_prism_params", &presets::scaled_prism_params, py::arg("blocks"),
        "Table 1 carried to any block count >= 2 (k_n, k_s as blocks^(1/3); law::scaled_prism_params)");
  bind_material_table<tie::params>(
      c, "study_tie_table", "contact::material_table of the study's bonded joint: params per pair of block materials");

  // ---- more geometry: boxes, prisms, cuts, random Voronoi tessellations, zoning options ----
  py::class_<aabb>(m, "aabb", "An axis-aligned box (m)")
      .def(py::init([](const vec3& lo, const vec3& hi) {
             require(lo.allFinite() && hi.allFinite() && (lo.array() < hi.array()).all(), "aabb: lo (", lo.transpose(),
                     ") m must be finite and below hi (", hi.transpose(), ") m in every axis");
             aabb b;
             b.lo = lo, b.hi = hi;
             return b;
           }),
           py::arg("lo"), py::arg("hi"))
      .def_readonly("lo", &aabb::lo, "lower corner (m)")
      .def_readonly("hi", &aabb::hi, "upper corner (m)")
      .def("size", &aabb::size, "hi - lo (m)")
      .def("volume", &aabb::volume, "volume (m^3)");
  py::class_<geometry::plane>(g, "plane", "The half-space n . x <= offset (n a unit normal, offset m)")
      .def(py::init([](const vec3& n, real offset) { return geometry::plane{n, offset}; }), py::arg("normal"),
           py::arg("offset"));
  g.def(
      "from_vertices", [](const std::vector<vec3>& p) { return geometry::convex_polyhedron::from_vertices(p); },
      py::arg("points"), "The convex hull of the points (m)");
  g.def(
      "prism", [](const std::vector<vec3>& polygon, const vec3& e) { return geometry::prism(polygon, e); },
      py::arg("polygon"), py::arg("extrusion"), "A convex polygon (m) extruded by the vector extrusion (m)");
  g.def("cylinder_prism", &geometry::cylinder_prism, py::arg("center"), py::arg("axis"), py::arg("radius"),
        py::arg("length"), py::arg("sides"), py::arg("phase") = 0.0,
        "A right prism of `sides` faces inscribed in a cylinder of radius (m) and length (m) about axis");
  g.def(
      "cut_by_planes",
      [](const geometry::convex_polyhedron& b, const std::vector<geometry::plane>& p) {
        return geometry::cut_by_planes(b, p);
      },
      py::arg("block"), py::arg("planes"), "The part of block inside every half-space");
  py::class_<geometry::tessellation_options>(g, "tessellation_options", "Regularisation of a random tessellation")
      .def(py::init<>())
      .def_readwrite("lloyd_iterations", &geometry::tessellation_options::lloyd_iterations, "Lloyd steps")
      .def_readwrite("min_spacing", &geometry::tessellation_options::min_spacing, "least generator spacing (m)")
      .def_readwrite("min_edge_rel", &geometry::tessellation_options::min_edge_rel,
                     "collapse edges shorter than this x the mean cell size");
  g.def(
      "random_voronoi",
      [](const aabb& box, index_t n, std::uint64_t seed, const geometry::tessellation_options& o) {
        return geometry::random_voronoi(box, n, seed, o);
      },
      py::arg("box"), py::arg("n"), py::arg("seed"), py::arg("options") = geometry::tessellation_options{},
      "Voronoi tessellation of the box (m) from n random generators (seed): the same cells for the same input");
  g.def(
      "random_voronoi",
      [](const geometry::convex_polyhedron& domain, index_t n, std::uint64_t seed, const geometry::tessellation_options& o) {
        return geometry::random_voronoi(domain, n, seed, o);
      },
      py::arg("domain"), py::arg("n"), py::arg("seed"), py::arg("options") = geometry::tessellation_options{},
      "Voronoi tessellation of a convex domain (m) from n random generators (seed)");
  g.def(
      "voronoi",
      [](const aabb& box, const std::vector<vec3>& seeds, const geometry::tessellation_options& o) {
        return geometry::voronoi(box, seeds, o);
      },
      py::arg("box"), py::arg("seeds"), py::arg("options") = geometry::tessellation_options{},
      "Voronoi tessellation of the box (m) from the given generators (m): cells that share their faces");
  py::class_<geometry::zoning_options>(g, "zoning_options", "How blocks are split into tetrahedral zones")
      .def(py::init<>())
      .def_readwrite("target_edge_length", &geometry::zoning_options::target_edge_length,
                     "zone edge target (m); 0 = one zone per face triangle")
      .def_readwrite("refine_interior", &geometry::zoning_options::refine_interior, "refine inside, not only faces");
  g.def(
      "zone_blocks",
      [](const geometry::tessellation& t, const geometry::zoning_options& o) { return geometry::zone_blocks(t, o); },
      py::arg("tess"), py::arg("options"), "Zones every block of tess with the given options");

  // ---- per-sub-contact state, energies, balance ----
  py::class_<contact_state>(m, "contact_state",
                            "Per-sub-contact state at one instant (NumPy copies, SI): write(path) gives a .vtp")
      .def("size", [](const contact_state& cs) { return cs.snapshot.size(); }, "Number of sub-contacts")
      .def_property_readonly("reference", [](const contact_state& cs) { return rows_of(cs.snapshot.reference); }, "reference position (m)")
      .def_property_readonly("displacement", [](const contact_state& cs) { return rows_of(cs.snapshot.displacement); }, "displacement (m)")
      .def_property_readonly("position", [](const contact_state& cs) { return rows_of(cs.position); },
                             "current position (m): contact.subcontact_position (face contacts: the mean of the two "
                             "gridpoints' positions; detected contacts: the mean of the two blocks' material points)")
      .def_property_readonly("force", [](const contact_state& cs) { return rows_of(cs.force); },
                             "force on block B's side in the last step (N); block A's side took its opposite")
      .def_property_readonly("normal", [](const contact_state& cs) { return rows_of(cs.snapshot.normal); }, "unit normal A->B")
      .def_property_readonly("area", [](const contact_state& cs) { return array_of(cs.snapshot.area); }, "area (m^2)")
      .def_property_readonly("tensile_damage", [](const contact_state& cs) { return array_of(cs.snapshot.tensile_damage); }, "0 intact .. 1 broken")
      .def_property_readonly("status", [](const contact_state& cs) { return array_of(cs.snapshot.status); }, "law::contact_status bits")
      .def_property_readonly("block_a", [](const contact_state& cs) { return array_of(cs.block_a); }, "block A")
      .def_property_readonly("block_b", [](const contact_state& cs) { return array_of(cs.block_b); }, "block B")
      .def("fields", [](const contact_state& cs) {
             std::vector<std::string> names;
             for (const auto& a : cs.snapshot.state) names.push_back(a.name);
             return names;
           }, "The names of the law's state fields, with their units (e.g. sigma_n_Pa)")
      .def("field", [](const contact_state& cs, const std::string& name) {
             const auto* a = cs.snapshot.find(name);
             require(a != nullptr, "contact_state: no field '", name, "'");
             py::array_t<double> out(a->components == 1 ? std::vector<py::ssize_t>{static_cast<py::ssize_t>(cs.snapshot.size())}
                                                       : std::vector<py::ssize_t>{static_cast<py::ssize_t>(cs.snapshot.size()), 3});
             std::copy(a->values.begin(), a->values.end(), out.mutable_data());
             return out;
           }, py::arg("name"), "One state field (n or n x 3), e.g. field('sigma_n_Pa')")
      .def("write", [](const contact_state& cs, const std::string& path) { cs.snapshot.write(path); }, py::arg("path"),
           "Writes the sub-contacts as a VTK .vtp (points with every field)");
  py::class_<out_of_balance>(m, "out_of_balance", "Unbalanced force of the last step (N)")
      .def_readonly("max_force", &out_of_balance::max_force, "largest |f| of a node over its free components (N)")
      .def_readonly("mean_force", &out_of_balance::mean_force, "mean of that magnitude (N)")
      .def_readonly("max_node", &out_of_balance::max_node, "the node of max_force");
  py::class_<integrator::mass_scaling_report>(m, "mass_scaling_report", "What mass scaling did (kg)")
      .def_readonly("added_mass", &integrator::mass_scaling_report::added_mass, "mass added (kg)")
      .def_readonly("original_mass", &integrator::mass_scaling_report::original_mass, "mass before scaling (kg)")
      .def_readonly("scaled_nodes", &integrator::mass_scaling_report::scaled_nodes, "nodes whose mass was raised");
  py::class_<energy_balance>(m, "energy_balance", "Energy terms (J)")
      .def_readonly("boundary_work", &energy_balance::boundary_work, "work of the support reactions (J)")
      .def_readonly("gravity_work", &energy_balance::gravity_work, "work of gravity (J)")
      .def_readonly("kinetic", &energy_balance::kinetic, "kinetic energy (J)")
      .def_readonly("block_elastic", &energy_balance::block_elastic, "elastic energy in the zones (J)")
      .def_readonly("contact_stored", &energy_balance::contact_stored, "elastic energy in the contact springs (J)")
      .def_readonly("contact_dissipated", &energy_balance::contact_dissipated, "dissipated by the contacts (J)")
      .def_readonly("damping_dissipated", &energy_balance::damping_dissipated, "removed by local damping (J)")
      .def_readonly("reinforcement_stored", &energy_balance::reinforcement_stored,
                    "elastic energy of bars and bond springs (J)")
      .def_readonly("reinforcement_dissipated", &energy_balance::reinforcement_dissipated,
                    "dissipated by bar yielding and bond slip (J)")
      .def_readonly("peak_work", &energy_balance::peak_work,
                    "largest |boundary| + |gravity| + |applied| work after any step so far (J; the step checker's bound)")
      .def("supplied", &energy_balance::supplied,
           "initial + boundary, gravity and applied work + the detected contacts' rebuild exchange (J)")
      .def("accounted", &energy_balance::accounted, "kinetic + stored + dissipated (J)")
      .def("error_rel", &energy_balance::error_rel, "|supplied - accounted| / |supplied|");
}

}  // namespace tessera::python
