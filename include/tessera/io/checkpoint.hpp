#pragma once
// Checkpoints: the whole evolving state of a solver in one binary file, so a run can be stopped
// and continued, or a state reached once (a cracked prism, a yielded tie) reused as the start of
// other loadings, with the same bits as a run that never stopped.
//
//     io::save_checkpoint(s, "run/peak.ckpt", "prism seed 1 at the peak");
//     ...                                   // build the same scene again (same tessellation,
//     io::load_checkpoint(t, "run/peak.ckpt");  // parameters, options, build), then load
//     t.run(1000);                          // bit-identical to s.run(1000)
//
// A checkpoint holds state, not the model: the scene is rebuilt by the caller and the file fills
// its evolving fields (displacements, velocities, masses and boundary flags of the gridpoints
// and bar nodes; block rotations and zone stresses, or rigid bodies' motion; every contact
// state field declared by the law (Law::state_fields) with the contact normals and forces; the
// bar and bond states; time, step, dt and the energy accounts).
//
// Each component writes its fields through one symmetric function, `template <class Archive>
// void checkpoint(Archive& ar)`, which saves or loads depending on the archive (so the two
// directions cannot drift apart). Archive calls:
//   ar.array(name, std::vector<T>& v)         v's values (real, float, integer, bool, enum, Eigen
//                                             fixed-size or quaternion elements)
//   ar.members(name, std::vector<S>& v, &S::m) member m of every element of v
//   ar.sized_array(name, std::vector<T>& v)   v's length, then its values: a vector that grows
//                                             during the run (a driver's samples); resized on load
//   ar.sized_records(size_name, v, records)   the same for any records of v's elements: its length,
//                                             then records(t) on v (or a dry-run scratch copy)
//   ar.matrix(name, M& m)                     an Eigen matrix's coefficients (sizes fixed by the model)
//   ar.scalar(name, T& x)                     one value
//   ar.same(name, value)                      saves value; on load requires the stored one to equal it
//   ar.count(name, std::int64_t& n)           a size the model takes from the file (state whose size
//                                             changes during a run, as detected contacts'): saves n;
//                                             on load sets n in both passes, so the dry run can check
//                                             the records that follow against it
//   ar.saving(), ar.loading()                 which pass this is (both false in the dry-run pass)
// A load runs the model's checkpoint() twice: a dry run that checks every record's name, type
// and length against the model without touching it, then the pass that copies. So a file of
// another scene is refused before anything changes.
//
// File (little-endian as written on this machine; format 1):
//   "TESSERA-CHECKPOINT\n", u32 format, u32 byte-order marker 0x01020304, u32 sizeof(real),
//   records { u32 name length, name, u8 type (1 f64, 2 i64, 3 u8), u64 count, count values },
//   the first three records "tessera/version", "tessera/commit", "description" (u8 text), the
//   last "end" (type 2, count 2: number of records before it, FNV-1a 64 hash of every byte before it).
// The file is written through io::atomic_ofstream: a killed run leaves the previous checkpoint
// (or none), never a partial one. Damaged or truncated files are refused by the hash.
//
// Errors: io_error for a file that cannot be opened, read or written; invalid_input naming the
// file and the record for a file that is not a checkpoint, of another format, damaged, or of
// another model (docs/errors.md).

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "../core/errors.hpp"
#include "../core/hash.hpp"
#include "../core/types.hpp"
#include "../core/version.hpp"
#include "atomic_file.hpp"

#ifndef TESSERA_GIT_COMMIT
#define TESSERA_GIT_COMMIT "unknown"  ///< the build's git commit, set by CMake; "unknown" outside it
#endif

namespace tessera::io {

inline constexpr std::uint32_t checkpoint_format = 1;

namespace detail::ckpt {

inline constexpr std::string_view magic = "TESSERA-CHECKPOINT\n";
inline constexpr std::uint32_t byte_order_marker = 0x01020304u;

enum class type_code : std::uint8_t { f64 = 1, i64 = 2, u8 = 3 };
[[nodiscard]] inline const char* type_name(type_code t) {
  return t == type_code::f64 ? "real" : t == type_code::i64 ? "integer" : t == type_code::u8 ? "byte" : "unknown";
}

/// How an element type is stored: `width` values of `code` each.
template <class T, class = void>
struct flat;
template <>
struct flat<real> {
  static constexpr type_code code = type_code::f64;
  static constexpr std::size_t width = 1;
  using value = real;
  static void get(const real& x, value* out) { *out = x; }
  static void put(real& x, const value* in) { x = *in; }
};
/// Single precision is stored as the real it widens to (exactly) and narrowed back (exactly).
template <>
struct flat<float> {
  static constexpr type_code code = type_code::f64;
  static constexpr std::size_t width = 1;
  using value = real;
  static void get(const float& x, value* out) { *out = static_cast<real>(x); }
  static void put(float& x, const value* in) { x = static_cast<float>(*in); }
};
template <class T>
struct flat<T, std::enable_if_t<std::is_integral_v<T> && !std::is_same_v<T, bool> && (sizeof(T) > 1)>> {
  static constexpr type_code code = type_code::i64;
  static constexpr std::size_t width = 1;
  using value = std::int64_t;
  static void get(const T& x, value* out) { *out = static_cast<std::int64_t>(x); }
  static void put(T& x, const value* in) { x = static_cast<T>(*in); }
};
template <class T>
struct flat<T, std::enable_if_t<std::is_same_v<T, bool> || std::is_enum_v<T> || (std::is_integral_v<T> && sizeof(T) == 1)>> {
  static constexpr type_code code = type_code::u8;
  static constexpr std::size_t width = 1;
  using value = std::uint8_t;
  static void get(const T& x, value* out) { *out = static_cast<std::uint8_t>(x); }
  static void put(T& x, const value* in) { x = static_cast<T>(*in); }
};
/// Eigen fixed-size real matrices and vectors (vec3, mat3): their coefficients in storage order.
template <class T>
struct flat<T, std::enable_if_t<std::is_base_of_v<Eigen::DenseBase<T>, T> && (T::SizeAtCompileTime > 0)>> {
  static constexpr type_code code = type_code::f64;
  static constexpr std::size_t width = static_cast<std::size_t>(T::SizeAtCompileTime);
  using value = real;
  static void get(const T& x, value* out) { std::copy_n(x.data(), width, out); }
  static void put(T& x, const value* in) { std::copy_n(in, width, x.data()); }
};
template <>
struct flat<Eigen::Quaterniond> {
  static constexpr type_code code = type_code::f64;
  static constexpr std::size_t width = 4;
  using value = real;
  static void get(const Eigen::Quaterniond& q, value* out) { std::copy_n(q.coeffs().data(), 4, out); }
  static void put(Eigen::Quaterniond& q, const value* in) { std::copy_n(in, 4, q.coeffs().data()); }
};

/// The calls every archive offers on top of its own values(): arrays, members, matrices, scalars.
template <class Derived>
class archive_base {
 public:
  template <class T>
  void array(std::string_view name, std::vector<T>& v) {
    elements(name, v.size(), [&](std::size_t i) -> T& { return v[i]; });
  }
  template <class S, class M>
  void members(std::string_view name, std::vector<S>& v, M S::*m) {
    elements(name, v.size(), [&](std::size_t i) -> M& { return v[i].*m; });
  }
  /// A vector whose length is state too (a driver's samples): its length under "<name>/size",
  /// then its values. A load resizes v to the file's length in the copying pass; the dry run
  /// checks the record on a scratch vector and leaves v as it is.
  template <class T>
  void sized_array(std::string_view name, std::vector<T>& v) {
    sized_records(std::string(name) + "/size", v, [&](std::vector<T>& t) { array(name, t); });
  }
  /// A vector that grows during the run, saved as its length (the record `size_name`) and then
  /// whatever `records(t)` saves of t (members of structs, nested sized arrays): t is v when saving
  /// or loading (a load resizes v to the file's length first), a scratch vector of the file's
  /// length in the dry run, so the records are checked without touching v.
  template <class T, class Records>
  void sized_records(std::string_view size_name, std::vector<T>& v, Records&& records) {
    std::int64_t n = static_cast<std::int64_t>(v.size());
    self().count(size_name, n);
    if (self().saving()) {
      records(v);
    } else if (self().loading()) {
      v.resize(static_cast<std::size_t>(n));
      records(v);
    } else {
      std::vector<T> dry(static_cast<std::size_t>(n));
      records(dry);
    }
  }
  /// An Eigen matrix of real or integer coefficients; its size is the model's (not resized).
  template <class M>
  void matrix(std::string_view name, M& m) {
    using T = typename M::Scalar;
    using F = flat<T>;
    if constexpr (std::is_same_v<T, typename F::value>)
      self().values(name, F::code, m.data(), static_cast<std::size_t>(m.size()));
    else
      elements(name, static_cast<std::size_t>(m.size()), [&](std::size_t i) -> T& { return m.data()[i]; });
  }
  template <class T>
  void scalar(std::string_view name, T& x) {
    using F = flat<T>;
    std::array<typename F::value, F::width> b{};
    if (self().saving()) F::get(x, b.data());
    self().values(name, F::code, b.data(), F::width);
    if (self().loading()) F::put(x, b.data());
  }

 private:
  Derived& self() { return static_cast<Derived&>(*this); }
  /// n elements, element(i) -> T&, through the buffer of T's stored type: gathered before a
  /// save, scattered after a load.
  template <class Element>
  void elements(std::string_view name, std::size_t n, Element&& element) {
    using T = std::remove_reference_t<decltype(element(std::size_t{}))>;
    using F = flat<T>;
    auto& b = buffer<typename F::value>();
    b.resize(n * F::width);
    if (self().saving())
      for (std::size_t i = 0; i < n; ++i) F::get(element(i), &b[i * F::width]);
    self().values(name, F::code, b.data(), b.size());
    if (self().loading())
      for (std::size_t i = 0; i < n; ++i) F::put(element(i), &b[i * F::width]);
  }
  template <class V>
  std::vector<V>& buffer() {
    if constexpr (std::is_same_v<V, real>)
      return reals_;
    else if constexpr (std::is_same_v<V, std::int64_t>)
      return integers_;
    else
      return bytes_;
  }
  std::vector<real> reals_;
  std::vector<std::int64_t> integers_;
  std::vector<std::uint8_t> bytes_;
};

}  // namespace detail::ckpt

/// Writes a checkpoint (see the file comment); the file appears at `target` only on commit().
class checkpoint_writer : public detail::ckpt::archive_base<checkpoint_writer> {
 public:
  using type_code = detail::ckpt::type_code;  ///< the record type tags
  checkpoint_writer(const std::filesystem::path& target, std::string_view description)
      : out_(target, std::ios::out | std::ios::trunc | std::ios::binary) {  ///< Opens target's temporary and writes the header with description; io_error when it cannot
    raw(detail::ckpt::magic.data(), detail::ckpt::magic.size());
    const std::array<std::uint32_t, 3> head{checkpoint_format, detail::ckpt::byte_order_marker,
                                             static_cast<std::uint32_t>(sizeof(real))};
    raw(head.data(), sizeof(head));
    text("tessera/version", TESSERA_VERSION_STRING);
    text("tessera/commit", TESSERA_GIT_COMMIT);
    text("description", description);
  }
  [[nodiscard]] static constexpr bool saving() { return true; }  ///< Writes
  [[nodiscard]] static constexpr bool loading() { return false; }  ///< Does not load

  void values(std::string_view name, type_code type, const void* data, std::size_t count) {  ///< Writes a record of count values of type under name
    const auto length = static_cast<std::uint32_t>(name.size());
    raw(&length, sizeof(length));
    raw(name.data(), name.size());
    raw(&type, 1);
    const auto n = static_cast<std::uint64_t>(count);
    raw(&n, sizeof(n));
    raw(data, count * (type == type_code::u8 ? 1 : 8));
    ++records_;
  }
  /// Saves `value`; a load requires the stored value to equal the model's.
  template <class T>
  void same(std::string_view name, T value) {
    scalar(name, value);
  }
  /// Saves the size n (loads give it back in both passes).
  void count(std::string_view name, std::int64_t& n) { values(name, type_code::i64, &n, 1); }
  /// Writes the end record and moves the file into place.
  void commit() {
    const std::array<std::uint64_t, 2> end{records_, hash_.value};
    values("end", type_code::i64, end.data(), 2);
    out_.commit();
  }

 private:
  void text(std::string_view name, std::string_view s) { values(name, type_code::u8, s.data(), s.size()); }
  void raw(const void* data, std::size_t n) {
    hash_.add(data, n);
    out_.stream().write(static_cast<const char*>(data), static_cast<std::streamsize>(n));
  }
  atomic_ofstream out_;
  fnv1a hash_;
  std::uint64_t records_ = 0;
};

/// What a checkpoint file says about itself (io::read_checkpoint_info).
struct checkpoint_info {
  std::uint32_t format = 0;  ///< file format version
  std::string version;      ///< tessera version that wrote it
  std::string commit;       ///< git commit of the build that wrote it ("unknown" outside the repository)
  std::string description;  ///< the text given to save_checkpoint
  std::uint64_t records = 0;  ///< number of records
  std::uint64_t bytes = 0;  ///< size of the file (bytes)
};

/// Reads a checkpoint: the whole file is read and its header, record structure and hash checked
/// at construction; values() then hands out the records in order (see the file comment).
class checkpoint_reader : public detail::ckpt::archive_base<checkpoint_reader> {
 public:
  using type_code = detail::ckpt::type_code;  ///< the record type tags
  explicit checkpoint_reader(const std::filesystem::path& file) : file_(file.string()) {  ///< Reads file and checks its header; io_error when it cannot be read, invalid_input when it is no checkpoint of this format
    std::ifstream in(file, std::ios::binary | std::ios::ate);
    if (!in) throw io_error(tessera::detail::concat("cannot open checkpoint '", file_, "': ", detail::last_os_error()));
    const auto size = static_cast<std::size_t>(in.tellg());
    data_.resize(size);
    in.seekg(0);
    in.read(reinterpret_cast<char*>(data_.data()), static_cast<std::streamsize>(size));
    if (!in) throw io_error(tessera::detail::concat("cannot read checkpoint '", file_, "': ", detail::last_os_error()));
    parse();
  }
  [[nodiscard]] bool saving() const { return false; }  ///< Does not write
  /// True in the pass that copies into the model; false in the dry run.
  [[nodiscard]] bool loading() const { return copy_; }
  [[nodiscard]] const checkpoint_info& info() const { return info_; }  ///< The header: version, commit, description, sizes

  /// Starts a pass over the data records: `copy` false checks them only.
  void rewind(bool copy) {
    next_ = first_data_;
    copy_ = copy;
  }
  void values(std::string_view name, type_code type, void* data, std::size_t count) {  ///< Checks the record's name, type and length against the model (invalid_input naming them), then copies it
    const record& r = expect(name, type, count);
    if (copy_ && count > 0) std::memcpy(data, data_.data() + r.offset, count * (type == type_code::u8 ? 1 : 8));
  }
  template <class T>
  void same(std::string_view name, T value) {  ///< Refuses (invalid_input) a saved value that differs from value, naming both
    using F = detail::ckpt::flat<T>;
    const record& r = expect(name, F::code, 1);
    typename F::value stored{};
    std::memcpy(&stored, data_.data() + r.offset, sizeof(stored));
    typename F::value mine{};
    F::get(value, &mine);
    require(std::memcmp(&stored, &mine, sizeof(stored)) == 0, "checkpoint '", file_, "' does not fit this model: ",
            name, " = ", +stored, " in the file but ", +mine,
            " in this model (rebuild the scene exactly as the run that wrote it: tessellation, parameters, options)");
  }
  /// The stored size `name`, in both passes (the dry run checks what follows against it).
  void count(std::string_view name, std::int64_t& n) {
    const record& r = expect(name, type_code::i64, 1);
    std::memcpy(&n, data_.data() + r.offset, sizeof(n));
    // Every value takes at least a byte of the file: a larger size is damage, refused before
    // anything is sized by it.
    require(n >= 0 && static_cast<std::uint64_t>(n) <= data_.size(), "checkpoint '", file_, "' has size ", n, " in '",
            name, "', impossible in a file of ", data_.size(), " bytes: damaged");
  }
  /// Requires every data record to have been read (after a pass).
  void finish() const {
    if (next_ != records_.size())
      throw invalid_input(tessera::detail::concat("checkpoint '", file_, "' has ", records_.size() - next_,
                                                  " record(s) this model does not read, the first '",
                                                  records_[next_].name, "' (written by another kind of model?)"));
  }

 private:
  struct record {
    std::string name;
    type_code type;
    std::uint64_t count;
    std::size_t offset;  ///< of the values in data_
  };
  [[noreturn]] void damaged(const std::string& what) const {
    throw invalid_input(tessera::detail::concat("checkpoint '", file_, "' ", what));
  }
  template <class T>
  T read_at(std::size_t at, const char* what) const {
    if (at + sizeof(T) > data_.size())
      damaged(tessera::detail::concat("ends at byte ", data_.size(), " inside ", what,
                                      ": the file is truncated (not written by a completed save?)"));
    T x;
    std::memcpy(&x, data_.data() + at, sizeof(T));
    return x;
  }
  void parse() {
    namespace c = detail::ckpt;
    if (data_.size() < c::magic.size() ||
        std::memcmp(data_.data(), c::magic.data(), c::magic.size()) != 0)
      damaged("is not a tessera checkpoint (it does not start with TESSERA-CHECKPOINT)");
    std::size_t at = c::magic.size();
    info_.format = read_at<std::uint32_t>(at, "the header");
    require(info_.format == checkpoint_format, "checkpoint '", file_, "' has format ", info_.format,
            "; this build of tessera reads format ", checkpoint_format);
    require(read_at<std::uint32_t>(at + 4, "the header") == c::byte_order_marker, "checkpoint '", file_,
            "' was written on a machine of the other byte order");
    require(read_at<std::uint32_t>(at + 8, "the header") == sizeof(real), "checkpoint '", file_,
            "' stores reals of ", read_at<std::uint32_t>(at + 8, "the header"), " bytes; this build uses ", sizeof(real));
    at += 12;
    fnv1a h;
    for (;;) {
      const auto length = read_at<std::uint32_t>(at, "a record header");
      if (length > 4096) damaged(tessera::detail::concat("has a record name of ", length, " bytes at byte ", at, ": damaged"));
      record r;
      r.name.assign(reinterpret_cast<const char*>(data_.data()) + at + 4,
                    std::min<std::size_t>(length, data_.size() - std::min(data_.size(), at + 4)));
      const std::size_t header_end = at + 4 + length + 1 + 8;
      const auto type = read_at<std::uint8_t>(at + 4 + length, "a record header");
      if (type < 1 || type > 3) damaged(tessera::detail::concat("has a record '", r.name, "' of unknown type ", +type, ": damaged"));
      r.type = static_cast<type_code>(type);
      r.count = read_at<std::uint64_t>(at + 4 + length + 1, "a record header");
      const std::uint64_t width = r.type == type_code::u8 ? 1 : 8;
      if (r.count > (data_.size() - std::min(data_.size(), header_end)) / width)
        damaged(tessera::detail::concat("ends inside record '", r.name, "' (", r.count, " values of ",
                                        c::type_name(r.type), " announced): the file is truncated"));
      r.offset = header_end;
      if (r.name == "end") {
        h.add(data_.data(), at);
        if (r.type != type_code::i64 || r.count != 2) damaged("has a malformed end record");
        const auto count = read_at<std::uint64_t>(header_end, "the end record");
        const auto stored = read_at<std::uint64_t>(header_end + 8, "the end record");
        if (stored != h.value || count != records_.size())
          damaged(tessera::detail::concat("fails its integrity check (hash ", stored, " stored, ", h.value,
                                          " computed): the file is damaged"));
        if (header_end + 16 != data_.size())
          damaged(tessera::detail::concat("has ", data_.size() - header_end - 16, " bytes after its end record"));
        break;
      }
      at = header_end + static_cast<std::size_t>(r.count * width);
      records_.push_back(std::move(r));
    }
    const auto text = [&](std::size_t i, const char* name) {
      if (records_.size() <= i || records_[i].name != name || records_[i].type != type_code::u8)
        damaged(tessera::detail::concat("lacks its '", name, "' record"));
      return std::string(reinterpret_cast<const char*>(data_.data()) + records_[i].offset, records_[i].count);
    };
    info_.version = text(0, "tessera/version");
    info_.commit = text(1, "tessera/commit");
    info_.description = text(2, "description");
    info_.records = records_.size();
    info_.bytes = data_.size();
    first_data_ = 3;
  }
  const record& expect(std::string_view name, type_code type, std::size_t count) {
    const auto mismatch = [&](const std::string& found) {
      return invalid_input(tessera::detail::concat(
          "checkpoint '", file_, "' does not fit this model: the model expects '", name, "' (", count, " ",
          detail::ckpt::type_name(type), " values) where the file has ", found,
          " (a different scene, seed, block model, law or reinforcement?)"));
    };
    if (next_ >= records_.size()) throw mismatch("no more records");
    const record& r = records_[next_];
    if (r.name != name || r.type != type || r.count != count)
      throw mismatch(tessera::detail::concat("'", r.name, "' (", r.count, " ", detail::ckpt::type_name(r.type), " values)"));
    ++next_;
    return r;
  }

  std::string file_;
  std::vector<std::uint8_t> data_;
  std::vector<record> records_;
  std::size_t first_data_ = 0, next_ = 0;
  bool copy_ = false;
  checkpoint_info info_;
};

/// The header of a checkpoint file, its structure and hash checked (for tools that list runs).
[[nodiscard]] inline checkpoint_info read_checkpoint_info(const std::filesystem::path& file) {
  return checkpoint_reader(file).info();
}

/// A model for save_checkpoint and load_checkpoint made of a callable `visit(ar)` that visits
/// the state in one order for both directions (a generic lambda `[&](auto& ar) {...}`: the solver's
/// checkpoint, a platen's, a driver's samples), for state that is not one object.
template <class F>
struct checkpoint_visitor {
  F visit;  ///< the visit, void(Archive&)
  template <class Archive>
  void checkpoint(Archive& ar) {  ///< Calls visit(ar)
    visit(ar);
  }
};
/// checkpoint_visitor of `visit` (copied; a lambda capturing by reference stays cheap).
template <class F>
[[nodiscard]] checkpoint_visitor<F> checkpoint_of(F visit) {
  return {std::move(visit)};
}

/// Writes `model`'s state (a tessera::solver, or anything with a symmetric checkpoint(Archive&))
/// to `file`, atomically; `description` is stored as text (checkpoint_info::description).
template <class Model>
void save_checkpoint(const Model& model, const std::filesystem::path& file, std::string_view description = {}) {
  checkpoint_writer w(file, description);
  // checkpoint() is one function for both directions; with a writer it only reads the model.
  const_cast<Model&>(model).checkpoint(w);
  w.commit();
}

/// Fills `model`, built as the model that wrote `file` was, with the state in `file`. Refuses
/// (invalid_input naming the first record that differs) before changing anything when the file
/// does not fit the model; returns the file's header.
template <class Model>
checkpoint_info load_checkpoint(Model& model, const std::filesystem::path& file) {
  checkpoint_reader r(file);
  r.rewind(false);
  model.checkpoint(r);
  r.finish();
  r.rewind(true);
  model.checkpoint(r);
  r.finish();
  return r.info();
}

}  // namespace tessera::io
