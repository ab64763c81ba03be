#pragma once
// VTK XML writers readable by ParaView (VTK file format version 1.0):
//  - unstructured_grid -> .vtu: points; cells of type vertex, line, polyline, triangle, polygon,
//    tetra and polyhedron (with the `faces`/`faceoffsets` arrays); point and cell data;
//  - poly_data -> .vtp: points, verts, lines, polys; point and cell data (contacts as points,
//    bars as polylines);
//  - pvd_collection -> .pvd: a time series of datasets (timestep = simulated time, s).
// Data arrays: Float64 or Int32 scalars, 3-vectors, and symmetric tensors stored as 6
// components in VTK's order (xx, yy, zz, xy, yz, xz), which ParaView shows as a tensor.
// Format: ascii (17 significant digits, exact round trip) or binary (inline base64 with a
// UInt64 byte-count header), selected per write() call.
// Every file is written atomically (io/atomic_file.hpp); failures throw io_error naming the path.
//
// Cost: the writer objects hold a copy of everything they will write; O(size) time and memory.
// Not thread-safe per object.

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <ostream>
#include <span>
#include <initializer_list>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "../geometry/tessellation.hpp"
#include "atomic_file.hpp"

namespace tessera::io::vtk {

/// VTK cell type ids (vtkCellType.h).
enum class cell_type : std::uint8_t {
  vertex = 1,
  line = 3,
  polyline = 4,
  triangle = 5,
  polygon = 7,
  tetra = 10,
  polyhedron = 42,
};

/// Symmetric tensor in VTK's component order: xx, yy, zz, xy, yz, xz (e.g. stress, Pa).
using sym_tensor = std::array<real, 6>;
[[nodiscard]] inline sym_tensor to_sym_tensor(const mat3& s) {
  return {s(0, 0), s(1, 1), s(2, 2), s(0, 1), s(1, 2), s(0, 2)};
}
/// Row z of a matrix of Voigt rows (xx yy zz yz zx xy: a zone_stress_matrix, Pa) in VTK's order.
template <class VoigtRows>
[[nodiscard]] sym_tensor voigt_row_to_sym_tensor(const VoigtRows& rows, Eigen::Index z) {
  return {rows(z, 0), rows(z, 1), rows(z, 2), rows(z, 5), rows(z, 3), rows(z, 4)};
}

enum class format { ascii, binary };

/// One named data array: Float64 or Int32 values, `components` per tuple.
struct data_array {
  std::string name;  ///< array name
  int components = 1;  ///< components per tuple
  bool is_integer = false;  ///< integer (Int32) rather than Float64
  std::vector<double> real_values;  ///< values when real
  std::vector<std::int32_t> int_values;  ///< values when integer
  [[nodiscard]] std::size_t tuples() const {  ///< Number of tuples
    return (is_integer ? int_values.size() : real_values.size()) / static_cast<std::size_t>(components);
  }
};

/// The point data or cell data of a dataset. Each add_* checks the tuple count when written.
class field_data {
 public:
  void add_scalar(std::string name, std::span<const double> values) {  ///< A real scalar per point or cell
    arrays_.push_back({std::move(name), 1, false, {values.begin(), values.end()}, {}});
  }
  void add_scalar(std::string name, std::span<const std::int32_t> values) {  ///< An integer scalar per point or cell
    arrays_.push_back({std::move(name), 1, true, {}, {values.begin(), values.end()}});
  }
  void add_vector(std::string name, std::span<const vec3> values) {  ///< A 3-vector per point or cell
    data_array a{std::move(name), 3, false, {}, {}};
    a.real_values.reserve(3 * values.size());
    for (const vec3& v : values) a.real_values.insert(a.real_values.end(), {v.x(), v.y(), v.z()});
    arrays_.push_back(std::move(a));
  }
  /// Vector per row of an N x 3 structure-of-arrays matrix (e.g. node_set::displacement).
  void add_vector(std::string name, const soa3& values) {
    data_array a{std::move(name), 3, false, {}, {}};
    a.real_values.reserve(3 * static_cast<std::size_t>(values.rows()));
    for (Eigen::Index i = 0; i < values.rows(); ++i)
      a.real_values.insert(a.real_values.end(), {values(i, 0), values(i, 1), values(i, 2)});
    arrays_.push_back(std::move(a));
  }
  void add_tensor(std::string name, std::span<const sym_tensor> values) {  ///< A symmetric tensor per point or cell (six components)
    data_array a{std::move(name), 6, false, {}, {}};
    a.real_values.reserve(6 * values.size());
    for (const auto& t : values) a.real_values.insert(a.real_values.end(), t.begin(), t.end());
    arrays_.push_back(std::move(a));
  }
  [[nodiscard]] const std::vector<data_array>& arrays() const { return arrays_; }  ///< The arrays
  [[nodiscard]] bool empty() const { return arrays_.empty(); }  ///< True without arrays

 private:
  std::vector<data_array> arrays_;
};

namespace detail {

inline void base64_encode(std::ostream& os, const std::vector<unsigned char>& bytes) {
  static constexpr char table[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const std::uint32_t v = (std::uint32_t{bytes[i]} << 16) | (std::uint32_t{bytes[i + 1]} << 8) | bytes[i + 2];
    os << table[(v >> 18) & 63] << table[(v >> 12) & 63] << table[(v >> 6) & 63] << table[v & 63];
  }
  if (const std::size_t rest = bytes.size() - i; rest > 0) {
    std::uint32_t v = std::uint32_t{bytes[i]} << 16;
    if (rest == 2) v |= std::uint32_t{bytes[i + 1]} << 8;
    os << table[(v >> 18) & 63] << table[(v >> 12) & 63] << (rest == 2 ? table[(v >> 6) & 63] : '=') << '=';
  }
}

template <class T>
[[nodiscard]] constexpr const char* vtk_type_name() {
  if constexpr (std::is_same_v<T, double>) return "Float64";
  else if constexpr (std::is_same_v<T, std::int32_t>) return "Int32";
  else if constexpr (std::is_same_v<T, std::int64_t>) return "Int64";
  else return "UInt8";
}

/// Writes one <DataArray> element holding `values` (tuples of `components`).
template <class T>
void write_data_array(std::ostream& os, const std::string& name, int components, std::span<const T> values, format fmt) {
  os << "        <DataArray type=\"" << vtk_type_name<T>() << '"';
  if (!name.empty()) os << " Name=\"" << name << '"';
  if (components != 1) os << " NumberOfComponents=\"" << components << '"';
  os << " format=\"" << (fmt == format::ascii ? "ascii" : "binary") << "\">\n";
  if (fmt == format::ascii) {
    os << "          ";
    std::size_t column = 0;
    for (const T& v : values) {
      if constexpr (std::is_same_v<T, std::uint8_t>) os << static_cast<int>(v);
      else if constexpr (std::is_floating_point_v<T>) {
        if (std::isfinite(v)) os << v;
        else os << (std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf"));
      } else os << v;
      os << (++column % 12 == 0 ? "\n          " : " ");
    }
    os << '\n';
  } else {
    const std::uint64_t n_bytes = values.size() * sizeof(T);
    std::vector<unsigned char> bytes(sizeof(std::uint64_t) + n_bytes);
    std::memcpy(bytes.data(), &n_bytes, sizeof(n_bytes));
    if (n_bytes > 0) std::memcpy(bytes.data() + sizeof(n_bytes), values.data(), n_bytes);
    os << "          ";
    base64_encode(os, bytes);
    os << '\n';
  }
  os << "        </DataArray>\n";
}

inline void write_field_data(std::ostream& os, const char* tag, const field_data& data, std::size_t expected_tuples,
                             const std::filesystem::path& path, format fmt) {
  if (data.empty()) return;
  os << "      <" << tag << ">\n";
  for (const data_array& a : data.arrays()) {
    require<io_error>(a.tuples() == expected_tuples, "writing '", path.string(), "': ", tag, " array '", a.name,
                      "' has ", a.tuples(), " tuples, expected ", expected_tuples);
    if (a.is_integer) write_data_array<std::int32_t>(os, a.name, a.components, a.int_values, fmt);
    else write_data_array<double>(os, a.name, a.components, a.real_values, fmt);
  }
  os << "      </" << tag << ">\n";
}

inline void write_header(std::ostream& os, const char* type) {
  os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"" << type
     << "\" version=\"1.0\" byte_order=\"" << (std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian")
     << "\" header_type=\"UInt64\">\n  <" << type << ">\n";
  os << std::setprecision(std::numeric_limits<double>::max_digits10);
}

inline void write_points(std::ostream& os, const std::vector<vec3>& points, format fmt) {
  std::vector<double> xyz;
  xyz.reserve(3 * points.size());
  for (const vec3& p : points) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  os << "      <Points>\n";
  write_data_array<double>(os, "Points", 3, xyz, fmt);
  os << "      </Points>\n";
}

}  // namespace detail

/// A .vtu unstructured grid. Point ids are the insertion order of add_point / set_points.
class unstructured_grid {
 public:
  field_data point_data;  ///< one tuple per point
  field_data cell_data;   ///< one tuple per cell, in add order

  void set_points(std::vector<vec3> points) { points_ = std::move(points); }  ///< Sets every point (m)
  index_t add_point(const vec3& p) {  ///< Adds a point (m), returns its id
    points_.push_back(p);
    return static_cast<index_t>(points_.size()) - 1;
  }
  /// Adds a cell of a fixed or variable node count (not polyhedron) and returns its id.
  index_t add_cell(cell_type type, std::span<const index_t> nodes) {
    require(type != cell_type::polyhedron, "vtk::unstructured_grid: use add_polyhedron for polyhedral cells");
    for (const index_t n : nodes) connectivity_.push_back(n);
    offsets_.push_back(static_cast<std::int64_t>(connectivity_.size()));
    types_.push_back(static_cast<std::uint8_t>(type));
    face_offsets_.push_back(-1);
    return static_cast<index_t>(types_.size()) - 1;
  }
  index_t add_cell(cell_type type, std::initializer_list<index_t> nodes) {  ///< Adds a cell of point ids (the span overload checks them), returns its id
    return add_cell(type, std::span<const index_t>(nodes.begin(), nodes.size()));
  }
  /// Adds a polyhedral cell given its faces (point loops, CCW seen from outside) and returns its id.
  /// The cell's point list is the distinct points of its faces in first-seen order.
  index_t add_polyhedron(std::span<const std::vector<index_t>> faces) {
    const std::size_t first = connectivity_.size();
    for (const auto& f : faces)
      for (const index_t n : f)
        if (std::find(connectivity_.begin() + static_cast<std::ptrdiff_t>(first), connectivity_.end(), n) == connectivity_.end())
          connectivity_.push_back(n);
    offsets_.push_back(static_cast<std::int64_t>(connectivity_.size()));
    types_.push_back(static_cast<std::uint8_t>(cell_type::polyhedron));
    faces_.push_back(static_cast<std::int64_t>(faces.size()));
    for (const auto& f : faces) {
      faces_.push_back(static_cast<std::int64_t>(f.size()));
      faces_.insert(faces_.end(), f.begin(), f.end());
    }
    face_offsets_.push_back(static_cast<std::int64_t>(faces_.size()));
    has_polyhedra_ = true;
    return static_cast<index_t>(types_.size()) - 1;
  }
  [[nodiscard]] index_t point_count() const { return static_cast<index_t>(points_.size()); }  ///< Number of points
  [[nodiscard]] index_t cell_count() const { return static_cast<index_t>(types_.size()); }  ///< Number of cells

  /// Writes the grid to `path` (.vtu) atomically.
  void write(const std::filesystem::path& path, format fmt = format::ascii) const {
    for (const std::int64_t n : connectivity_)
      require<io_error>(n >= 0 && n < static_cast<std::int64_t>(points_.size()), "writing '", path.string(),
                        "': cell refers to point ", n, ", expected < ", points_.size());
    atomic_ofstream out(path);
    std::ostream& os = out.stream();
    detail::write_header(os, "UnstructuredGrid");
    os << "    <Piece NumberOfPoints=\"" << points_.size() << "\" NumberOfCells=\"" << types_.size() << "\">\n";
    detail::write_field_data(os, "PointData", point_data, points_.size(), path, fmt);
    detail::write_field_data(os, "CellData", cell_data, types_.size(), path, fmt);
    detail::write_points(os, points_, fmt);
    os << "      <Cells>\n";
    detail::write_data_array<std::int64_t>(os, "connectivity", 1, connectivity_, fmt);
    detail::write_data_array<std::int64_t>(os, "offsets", 1, offsets_, fmt);
    detail::write_data_array<std::uint8_t>(os, "types", 1, types_, fmt);
    if (has_polyhedra_) {
      detail::write_data_array<std::int64_t>(os, "faces", 1, faces_, fmt);
      detail::write_data_array<std::int64_t>(os, "faceoffsets", 1, face_offsets_, fmt);
    }
    os << "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
    out.commit();
  }

 private:
  std::vector<vec3> points_;
  std::vector<std::int64_t> connectivity_, offsets_, faces_, face_offsets_;
  std::vector<std::uint8_t> types_;
  bool has_polyhedra_ = false;
};

/// A .vtp poly data set. Cell ids (for cell_data) run over verts first, then lines, then
/// polys, each in add order, which is how VTK numbers them.
class poly_data {
 public:
  field_data point_data;  ///< one tuple per point
  field_data cell_data;   ///< one tuple per cell: verts, then lines, then polys

  void set_points(std::vector<vec3> points) { points_ = std::move(points); }  ///< Sets every point (m)
  index_t add_point(const vec3& p) {  ///< Adds a point (m), returns its id
    points_.push_back(p);
    return static_cast<index_t>(points_.size()) - 1;
  }
  void add_vertex(index_t p) { verts_.add({&p, 1}); }  ///< Adds a vertex cell
  /// A polyline through the given points (a bar as a chain of truss elements).
  void add_line(std::span<const index_t> points) { lines_.add(points); }
  void add_polygon(std::span<const index_t> points) { polys_.add(points); }  ///< Adds a polygon cell
  [[nodiscard]] index_t point_count() const { return static_cast<index_t>(points_.size()); }  ///< Number of points
  [[nodiscard]] index_t cell_count() const {  ///< Number of cells
    return static_cast<index_t>(verts_.offsets.size() + lines_.offsets.size() + polys_.offsets.size());
  }

  void write(const std::filesystem::path& path, format fmt = format::ascii) const {  ///< Writes the .vtp file (io_error when it cannot)
    atomic_ofstream out(path);
    std::ostream& os = out.stream();
    detail::write_header(os, "PolyData");
    os << "    <Piece NumberOfPoints=\"" << points_.size() << "\" NumberOfVerts=\"" << verts_.offsets.size()
       << "\" NumberOfLines=\"" << lines_.offsets.size() << "\" NumberOfStrips=\"0\" NumberOfPolys=\""
       << polys_.offsets.size() << "\">\n";
    detail::write_field_data(os, "PointData", point_data, points_.size(), path, fmt);
    detail::write_field_data(os, "CellData", cell_data, static_cast<std::size_t>(cell_count()), path, fmt);
    detail::write_points(os, points_, fmt);
    const auto section = [&](const char* tag, const cell_list& cells) {
      if (cells.offsets.empty()) return;
      for (const std::int64_t n : cells.connectivity)
        require<io_error>(n >= 0 && n < static_cast<std::int64_t>(points_.size()), "writing '", path.string(), "': ",
                          tag, " refers to point ", n, ", expected < ", points_.size());
      os << "      <" << tag << ">\n";
      detail::write_data_array<std::int64_t>(os, "connectivity", 1, cells.connectivity, fmt);
      detail::write_data_array<std::int64_t>(os, "offsets", 1, cells.offsets, fmt);
      os << "      </" << tag << ">\n";
    };
    section("Verts", verts_);
    section("Lines", lines_);
    section("Polys", polys_);
    os << "    </Piece>\n  </PolyData>\n</VTKFile>\n";
    out.commit();
  }

 private:
  struct cell_list {
    std::vector<std::int64_t> connectivity, offsets;
    void add(std::span<const index_t> p) {
      connectivity.insert(connectivity.end(), p.begin(), p.end());
      offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
    }
  };
  std::vector<vec3> points_;
  cell_list verts_, lines_, polys_;
};

/// A .pvd collection: a list of (time, file) entries, rewritten atomically by write().
/// File names are stored relative to the .pvd's directory when they are inside it.
class pvd_collection {
 public:
  /// Registers dataset `file` at simulated time `time` (s); `part` distinguishes datasets of
  /// the same time step (e.g. 0 = zones, 1 = contacts).
  void add(double time, const std::filesystem::path& file, int part = 0) { entries_.push_back({time, part, file}); }
  [[nodiscard]] std::size_t size() const { return entries_.size(); }  ///< Number of entries

  void write(const std::filesystem::path& path) const {  ///< Writes the .pvd file (io_error when it cannot)
    atomic_ofstream out(path);
    std::ostream& os = out.stream();
    os << std::setprecision(std::numeric_limits<double>::max_digits10);
    os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n  <Collection>\n";
    const std::filesystem::path dir = path.parent_path();
    for (const auto& e : entries_) {
      std::filesystem::path file = e.file;
      if (file.is_absolute() && !dir.empty()) {
        std::error_code ec;
        const auto rel = std::filesystem::relative(file, std::filesystem::absolute(dir, ec), ec);
        if (!ec && !rel.empty()) file = rel;
      } else if (!dir.empty()) {
        const auto rel = file.lexically_relative(dir);
        if (!rel.empty() && *rel.begin() != "..") file = rel;
      }
      os << "    <DataSet timestep=\"" << e.time << "\" group=\"\" part=\"" << e.part << "\" file=\""
         << file.generic_string() << "\"/>\n";
    }
    os << "  </Collection>\n</VTKFile>\n";
    out.commit();
  }

 private:
  struct entry {
    double time;
    int part;
    std::filesystem::path file;
  };
  std::vector<entry> entries_;
};

/// Writes the cells of a tessellation as VTK polyhedra (type 42) with cell data `block` (Int32
/// cell id) and `volume` (m^3, divergence theorem over the fan-triangulated faces).
TESSERA_INLINE void write_blocks_vtu(const std::filesystem::path& path, const geometry::tessellation& tess,
                                     format fmt = format::ascii);

/// Optional per-gridpoint and per-zone fields of write_zones_vtu.
struct zone_fields {
  const soa3* displacement = nullptr;       ///< per gridpoint (m); ParaView: Warp By Vector
  std::span<const sym_tensor> stress;        ///< per zone (Pa), tension positive
};

/// Writes the tetrahedral zones of a block mesh (reference positions) with cell data `block`
/// (Int32) and the optional displacement (point data) and stress (cell data) fields.
inline void write_zones_vtu(const std::filesystem::path& path, const geometry::block_mesh& mesh,
                            const zone_fields& fields = {}, format fmt = format::ascii) {
  unstructured_grid grid;
  grid.set_points(mesh.gridpoints);
  for (const auto& z : mesh.zones) grid.add_cell(cell_type::tetra, z);
  grid.cell_data.add_scalar("block", std::span<const std::int32_t>(mesh.zone_block));
  grid.point_data.add_scalar("block", std::span<const std::int32_t>(mesh.gridpoint_block));
  if (fields.displacement != nullptr) grid.point_data.add_vector("displacement", *fields.displacement);
  if (!fields.stress.empty()) grid.cell_data.add_tensor("stress", fields.stress);
  grid.write(path, fmt);
}

}  // namespace tessera::io::vtk

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/vtk.ipp"
#endif
