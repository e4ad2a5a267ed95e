// vtk.cpp — writing .vtp and .pvd documents with fmt (VTK XML file format, PolyData).
#include "cdpowder/io/vtk.hpp"

#include "cdpowder/analysis/coordination.hpp"
#include "cdpowder/contact/contact_view.hpp"
#include "cdpowder/io/atomic_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string_view>
#include <type_traits>
#include <vector>
#include <zlib.h>

namespace cdpowder {

namespace {

using Buffer = fmt::memory_buffer;

/// Contact kinds in the contact network's "kind" array.
constexpr int kKindPair = 0;
constexpr int kKindBottom = 1;
constexpr int kKindPiston = 2;

/// Cell kinds in the walls' "kind" array.
constexpr int kWallsKindBottom = 0;
constexpr int kWallsKindPiston = 1;
constexpr int kWallsKindCellEdge = 2;

/// The files of one snapshot, DIR/snapshots/KIND_NNNNNN.vtp, each with its DIR/KIND.pvd.
constexpr std::array<const char*, 3> kSnapshotKinds{"particles", "contacts", "walls"};

/// Base64 (RFC 4648, with padding) of `size` bytes.
void append_base64(const unsigned char* bytes, std::size_t size, std::string& out) {
  static constexpr std::string_view kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  for (std::size_t i = 0; i < size; i += 3) {
    const std::size_t n = std::min<std::size_t>(3, size - i);
    std::uint32_t group = std::uint32_t{bytes[i]} << 16U;
    if (n > 1) group |= std::uint32_t{bytes[i + 1]} << 8U;
    if (n > 2) group |= std::uint32_t{bytes[i + 2]};
    out += kAlphabet[(group >> 18U) & 63U];
    out += kAlphabet[(group >> 12U) & 63U];
    out += n > 1 ? kAlphabet[(group >> 6U) & 63U] : '=';
    out += n > 2 ? kAlphabet[group & 63U] : '=';
  }
}

/// VTK's compressed block size (vtkDataCompressor's default) [bytes].
constexpr std::size_t kZlibBlockBytes = 32768;

/// `bytes` as VTK's vtkZLibDataCompressor lays it out for header_type UInt64: the block count,
/// the block size, the size of the last block when it is partial (else 0), the compressed
/// size of every block, then the compressed blocks, one after the other.
std::string zlib_blocks(const char* bytes, std::size_t size) {
  const std::size_t blocks = (size + kZlibBlockBytes - 1) / kZlibBlockBytes;
  std::vector<std::uint64_t> header{blocks, kZlibBlockBytes, size % kZlibBlockBytes};
  std::string data;
  std::vector<Bytef> packed(compressBound(kZlibBlockBytes));
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t n = std::min(kZlibBlockBytes, size - b * kZlibBlockBytes);
    uLongf packed_size = packed.size();
    if (compress2(packed.data(), &packed_size,
                  reinterpret_cast<const Bytef*>(bytes + b * kZlibBlockBytes), n, 5) != Z_OK) {
      throw std::runtime_error("zlib could not compress a VTK array");
    }
    header.push_back(packed_size);
    data.append(reinterpret_cast<const char*>(packed.data()), packed_size);
  }
  std::string out(reinterpret_cast<const char*>(header.data()),
                  header.size() * sizeof(std::uint64_t));
  return out + data;
}

/// A .vtp document: the XML with each data array inline as text (VtkFormat::Ascii) or
/// referring by offset into an <AppendedData> section: base64 blocks (VtkFormat::Binary), each
/// the array's byte count (UInt64, the header_type) and then its bytes, encoded one after the
/// other, or raw zlib blocks (VtkFormat::Zlib, vtkZLibDataCompressor's layout: zlib_blocks).
/// Little-endian, as the file declares (x86-64).
class VtpDocument {
 public:
  VtpDocument(VtkFormat format, OutputSink& sink)
      : chunks_(sink),
        sink_(&sink),
        binary_(format == VtkFormat::Binary || format == VtkFormat::Zlib),
        zlib_(format == VtkFormat::Zlib) {}

  /// XML text, as it is.
  template <typename... Args>
  void xml(fmt::format_string<Args...> text, Args&&... args) {
    fmt::format_to(std::back_inserter(chunks_.text()), text, std::forward<Args>(args)...);
    chunks_.chunk_done();
  }

  /// <DataArray> of `values`, `components` per tuple; `type` is VTK's name of T.
  template <typename T>
  void array(const char* type, const char* name, int components, const std::vector<T>& values) {
    if (binary_) {
      xml("<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"appended\" "
          "offset=\"{}\"/>\n",
          type, name, components, appended_.size());
      const std::uint64_t bytes = values.size() * sizeof(T);
      if (zlib_) {
        appended_ += zlib_blocks(reinterpret_cast<const char*>(values.data()), bytes);
        return;
      }
      // the byte count and the bytes, encoded as one block
      std::string block(reinterpret_cast<const char*>(&bytes), sizeof(bytes));
      if (bytes > 0) block.append(reinterpret_cast<const char*>(values.data()), bytes);
      append_base64(reinterpret_cast<const unsigned char*>(block.data()), block.size(), appended_);
      return;
    }
    xml("<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">\n", type,
        name, components);
    std::string& out = chunks_.text();
    for (std::size_t i = 0; i < values.size(); ++i) {
      if constexpr (std::is_floating_point_v<T>) {
        fmt::format_to(std::back_inserter(out), "{:.9g}", values[i]);
      } else {
        fmt::format_to(std::back_inserter(out), "{}", values[i]);
      }
      out.push_back((i + 1) % static_cast<std::size_t>(components) == 0 ? '\n' : ' ');
      chunks_.chunk_done();
    }
    xml("</DataArray>\n");
  }

  void doubles(const char* name, const std::vector<double>& values, int components = 1) {
    array("Float64", name, components, values);
  }

  void vectors(const char* name, const std::vector<Vec3>& values) {
    std::vector<double> flat;
    flat.reserve(3 * values.size());
    for (const Vec3& v : values) flat.insert(flat.end(), {v.x(), v.y(), v.z()});
    array("Float64", name, 3, flat);
  }

  void ints(const char* name, const std::vector<std::int32_t>& values) {
    array("Int32", name, 1, values);
  }

  /// Connectivity and offsets of `cells` cells of `size` consecutive points each, the first
  /// at point `first_point`.
  void cells(const char* section, std::size_t cells, std::size_t size,
             std::size_t first_point = 0) {
    std::vector<std::int64_t> connectivity(cells * size);
    std::vector<std::int64_t> offsets(cells);
    for (std::size_t i = 0; i < connectivity.size(); ++i) {
      connectivity[i] = static_cast<std::int64_t>(first_point + i);
    }
    for (std::size_t k = 0; k < cells; ++k) offsets[k] = static_cast<std::int64_t>((k + 1) * size);
    xml("<{}>\n", section);
    array("Int64", "connectivity", 1, connectivity);
    array("Int64", "offsets", 1, offsets);
    xml("</{}>\n", section);
  }

  /// Opens the VTKFile and its one Piece.
  void begin_polydata(std::size_t points, std::size_t verts, std::size_t lines,
                      std::size_t polys = 0) {
    xml("<?xml version=\"1.0\"?>\n"
        "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
        "header_type=\"UInt64\"{}>\n"
        "<PolyData>\n"
        "<Piece NumberOfPoints=\"{}\" NumberOfVerts=\"{}\" NumberOfLines=\"{}\" "
        "NumberOfStrips=\"0\" NumberOfPolys=\"{}\">\n",
        zlib_ ? " compressor=\"vtkZLibDataCompressor\"" : "", points, verts, lines, polys);
  }

  /// Closes the Piece and the document (with the appended data of a binary one), and hands
  /// the rest to the sink. The appended data (compressed, or base64) is the one part held
  /// until the end: its offsets are in the XML before it.
  void finish() {
    xml("</Piece>\n</PolyData>\n");
    if (binary_) {
      // raw bytes after the underscore, as VTK's own writer appends them, or base64
      xml("<AppendedData encoding=\"{}\">\n_", zlib_ ? "raw" : "base64");
      chunks_.finish();
      sink_->write(appended_);
      xml("\n</AppendedData>\n");
    }
    xml("</VTKFile>\n");
    chunks_.finish();
  }

 private:
  ChunkedText chunks_;
  OutputSink* sink_;
  std::string appended_;
  bool binary_;
  bool zlib_;
};

/// One closed contact of the network, in output form.
struct NetworkLine {
  Vec3 from;
  Vec3 to;
  Vec3 normal;  ///< n, from a to b (from the wall into the sphere)
  Vec3 force;   ///< R_n n + R_t: the force on b (on the sphere of a wall contact) [F_coh]
  double normal_force;
  double tangential_force;
  bool cohesive;
  int kind;
  BodyIndex owner;  ///< whose rank writes the line: a pair's a, a wall contact's sphere
};

std::vector<NetworkLine> network_lines(const World& world, const Contacts& contacts) {
  std::vector<NetworkLine> lines;
  const Bodies& bodies = world.bodies;
  for_each_contact(contacts, [&](const ContactView& c) {
    const ContactAction& action = *c.action;
    // open contacts are left out; a force that is not a number is drawn (a failed state)
    if (!c.closed() && !std::isnan(action.normal_force)) return;
    const Vec3 force = action.normal_force * c.normal + action.tangential_force;
    const double tangential = action.tangential_force.norm();
    const Vec3& b = bodies.position[c.b];
    if (c.is_pair()) {
      const Vec3& a = bodies.position[c.a];
      lines.push_back({a, a + world.box.minimum_image(b - a), c.normal, force, action.normal_force,
                       tangential, c.cohesive, kKindPair, c.a});
      return;
    }
    // n points from the wall into the sphere: the contact point is R behind the centre
    lines.push_back({b, b - bodies.radius[c.b] * c.normal, c.normal, force, action.normal_force,
                     tangential, c.cohesive,
                     *c.wall == WallKind::Bottom ? kKindBottom : kKindPiston, c.b});
  });
  return lines;
}

std::string pvd(const std::vector<std::pair<double, std::string>>& entries,
                const std::string& prefix) {
  Buffer out;
  fmt::format_to(std::back_inserter(out),
                 "<?xml version=\"1.0\"?>\n"
                 "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
                 "<Collection>\n");
  for (const auto& [time, suffix] : entries) {
    fmt::format_to(std::back_inserter(out),
                   "<DataSet timestep=\"{}\" group=\"\" part=\"0\" "
                   "file=\"snapshots/{}_{}.vtp\"/>\n",
                   time, prefix, suffix);
  }
  fmt::format_to(std::back_inserter(out), "</Collection>\n</VTKFile>\n");
  return fmt::to_string(out);
}

}  // namespace

namespace {

/// The particles of `world`, or those of `selection` (sphere indices, ascending), as a .vtp
/// document.
void particles_document(OutputSink& sink, const World& world, const Contacts* contacts,
                        const std::vector<BodyIndex>* selection, VtkFormat format) {
  const Bodies& bodies = world.bodies;
  const std::vector<int> coordination =
      contacts != nullptr ? contacts_per_sphere(*contacts, bodies.size()) : std::vector<int>{};
  std::vector<std::int64_t> ids;
  std::vector<Vec3> position;
  std::vector<double> radius;
  std::vector<Vec3> velocity;
  std::vector<Vec3> angular_velocity;
  std::vector<std::int32_t> coordinated;
  const auto take = [&](std::size_t i) {
    ids.push_back(static_cast<std::int64_t>(i));
    if (selection == nullptr) return;  // the whole arrays are written as they are
    position.push_back(bodies.position[i]);
    radius.push_back(bodies.radius[i]);
    velocity.push_back(bodies.velocity[i]);
    angular_velocity.push_back(bodies.angular_velocity[i]);
    if (contacts != nullptr) coordinated.push_back(coordination[i]);
  };
  if (selection == nullptr) {
    for (std::size_t i = 0; i < bodies.size(); ++i) take(i);
    if (contacts != nullptr) coordinated.assign(coordination.begin(), coordination.end());
  } else {
    for (const BodyIndex i : *selection) take(i);
  }
  const bool whole = selection == nullptr;
  const std::size_t n = ids.size();
  VtpDocument doc(format, sink);
  doc.begin_polydata(n, n, 0);
  doc.xml("<Points>\n");
  doc.vectors("Points", whole ? bodies.position : position);
  doc.xml("</Points>\n");
  doc.cells("Verts", n, 1);
  doc.xml("<PointData Scalars=\"radius\" Vectors=\"velocity\">\n");
  doc.array("Int64", "id", 1, ids);
  doc.doubles("radius", whole ? bodies.radius : radius);
  doc.vectors("velocity", whole ? bodies.velocity : velocity);
  doc.vectors("angular_velocity", whole ? bodies.angular_velocity : angular_velocity);
  if (contacts != nullptr) doc.ints("coordination", coordinated);
  doc.xml("</PointData>\n");
  doc.finish();
}

/// `lines` as a .vtp document of lines.
void contacts_document(OutputSink& sink, const std::vector<NetworkLine>& lines, VtkFormat format) {
  const std::size_t n = lines.size();
  std::vector<Vec3> points;
  std::vector<Vec3> forces;
  std::vector<Vec3> normals;
  std::vector<double> normal_force;
  std::vector<double> tangential_force;
  std::vector<std::int32_t> tensile;
  std::vector<std::int32_t> cohesive;
  std::vector<std::int32_t> kind;
  for (const NetworkLine& line : lines) {
    points.push_back(line.from);
    points.push_back(line.to);
    forces.push_back(line.force);
    normals.push_back(line.normal);
    normal_force.push_back(line.normal_force);
    tangential_force.push_back(line.tangential_force);
    tensile.push_back(line.normal_force < 0.0 ? 1 : 0);
    cohesive.push_back(line.cohesive ? 1 : 0);
    kind.push_back(line.kind);
  }
  VtpDocument doc(format, sink);
  doc.begin_polydata(2 * n, 0, n);
  doc.xml("<Points>\n");
  doc.vectors("Points", points);
  doc.xml("</Points>\n");
  doc.cells("Lines", n, 2);
  doc.xml("<CellData Scalars=\"normal_force\" Vectors=\"force\" Normals=\"normal\">\n");
  doc.doubles("normal_force", normal_force);
  doc.vectors("force", forces);
  doc.vectors("normal", normals);
  doc.ints("tensile", tensile);
  doc.doubles("tangential_force", tangential_force);
  doc.ints("cohesive", cohesive);
  doc.ints("kind", kind);
  doc.xml("</CellData>\n");
  doc.finish();
}

/// A data array a .pvtp declares: VTK's type name, the array's name, components per tuple.
struct DeclaredArray {
  const char* type;
  const char* name;
  int components;
};

/// A .pvtp over `pieces` files KIND/KIND_r.vtp that declares their points and the `arrays` of
/// their `data_section` (PointData or CellData, with its `attributes`).
std::string pvtp(std::string_view kind, int pieces, std::string_view data_section,
                 std::string_view attributes, const std::vector<DeclaredArray>& arrays) {
  Buffer out;
  fmt::format_to(std::back_inserter(out),
                 "<?xml version=\"1.0\"?>\n"
                 "<VTKFile type=\"PPolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
                 "header_type=\"UInt64\">\n"
                 "<PPolyData GhostLevel=\"0\">\n"
                 "<PPoints>\n<PDataArray type=\"Float64\" Name=\"Points\" "
                 "NumberOfComponents=\"3\"/>\n</PPoints>\n"
                 "<P{} {}>\n",
                 data_section, attributes);
  for (const DeclaredArray& a : arrays) {
    fmt::format_to(std::back_inserter(out),
                   "<PDataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\"/>\n", a.type,
                   a.name, a.components);
  }
  fmt::format_to(std::back_inserter(out), "</P{}>\n", data_section);
  for (int r = 0; r < pieces; ++r) {
    fmt::format_to(std::back_inserter(out), "<Piece Source=\"{}/{}_{}.vtp\"/>\n", kind, kind, r);
  }
  fmt::format_to(std::back_inserter(out), "</PPolyData>\n</VTKFile>\n");
  return fmt::to_string(out);
}

}  // namespace

void write_particles_vtp(OutputSink& sink, const World& world, const Contacts* contacts,
                         VtkFormat format) {
  particles_document(sink, world, contacts, nullptr, format);
}

void write_contacts_vtp(OutputSink& sink, const World& world, const Contacts& contacts,
                        VtkFormat format) {
  contacts_document(sink, network_lines(world, contacts), format);
}

void write_particles_piece(OutputSink& sink, const World& world, const Contacts* contacts,
                           const std::vector<int>& sphere_rank, int rank, VtkFormat format) {
  std::vector<BodyIndex> mine;
  for (std::size_t i = 0; i < sphere_rank.size(); ++i) {
    if (sphere_rank[i] == rank) mine.push_back(static_cast<BodyIndex>(i));
  }
  particles_document(sink, world, contacts, &mine, format);
}

void write_contacts_piece(OutputSink& sink, const World& world, const Contacts& contacts,
                          const std::vector<int>& sphere_rank, int rank, VtkFormat format) {
  std::vector<NetworkLine> lines = network_lines(world, contacts);
  std::erase_if(lines, [&](const NetworkLine& line) { return sphere_rank[line.owner] != rank; });
  contacts_document(sink, lines, format);
}

std::string particles_pvtp(int pieces, bool with_coordination) {
  std::vector<DeclaredArray> arrays{{"Int64", "id", 1},
                                    {"Float64", "radius", 1},
                                    {"Float64", "velocity", 3},
                                    {"Float64", "angular_velocity", 3}};
  if (with_coordination) arrays.push_back({"Int32", "coordination", 1});
  return pvtp("particles", pieces, "PointData", R"(Scalars="radius" Vectors="velocity")", arrays);
}

std::string contacts_pvtp(int pieces) {
  return pvtp("contacts", pieces, "CellData",
              R"(Scalars="normal_force" Vectors="force" Normals="normal")",
              {{"Float64", "normal_force", 1},
               {"Float64", "force", 3},
               {"Float64", "normal", 3},
               {"Int32", "tensile", 1},
               {"Float64", "tangential_force", 1},
               {"Int32", "cohesive", 1},
               {"Int32", "kind", 1}});
}

void write_walls_vtp(OutputSink& sink, const World& world, VtkFormat format) {
  const Bodies& bodies = world.bodies;
  const Walls& walls = world.walls;
  const double lx = world.box.lx;
  const double ly = world.box.ly;
  // the cell's four vertical edges reach the piston, or the highest sphere top without one
  double top = walls.piston.enabled ? walls.piston.height : 0.0;
  if (!walls.piston.enabled) {
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      top = std::max(top, bodies.position[i].z() + bodies.radius[i]);
    }
  }
  constexpr std::array<std::array<double, 2>, 4> kCorners{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
  std::vector<Vec3> points;
  for (const auto& [x, y] : kCorners) {
    points.emplace_back(x * lx, y * ly, 0.0);
    points.emplace_back(x * lx, y * ly, top);
  }
  std::vector<std::int32_t> kinds(4, kWallsKindCellEdge);  // the lines first, then the polys
  const auto add_plane = [&](double z, int kind) {
    for (const auto& [x, y] : kCorners) points.emplace_back(x * lx, y * ly, z);
    kinds.push_back(kind);
  };
  if (walls.bottom.enabled) add_plane(0.0, kWallsKindBottom);
  if (walls.piston.enabled) add_plane(walls.piston.height, kWallsKindPiston);
  const std::size_t planes = kinds.size() - 4;
  VtpDocument doc(format, sink);
  doc.begin_polydata(points.size(), 0, 4, planes);
  doc.xml("<Points>\n");
  doc.vectors("Points", points);
  doc.xml("</Points>\n");
  doc.cells("Lines", 4, 2);
  doc.cells("Polys", planes, 4, 8);
  doc.xml("<CellData Scalars=\"kind\">\n");
  doc.ints("kind", kinds);
  doc.xml("</CellData>\n");
  doc.finish();
}

std::string particles_vtp(const World& world, const Contacts* contacts, VtkFormat format) {
  return written_text(
      [&](OutputSink& sink) { write_particles_vtp(sink, world, contacts, format); });
}

std::string contacts_vtp(const World& world, const Contacts& contacts, VtkFormat format) {
  return written_text([&](OutputSink& sink) { write_contacts_vtp(sink, world, contacts, format); });
}

std::string walls_vtp(const World& world, VtkFormat format) {
  return written_text([&](OutputSink& sink) { write_walls_vtp(sink, world, format); });
}

std::vector<double> VtkSnapshotSeries::read_earlier() {
  entries_.clear();
  const std::filesystem::path file = out_dir_ / "particles.pvd";
  std::ifstream in(file);
  std::vector<double> times;
  if (!in) return times;
  const std::string time_key = "timestep=\"";
  const std::string file_key = "file=\"snapshots/particles_";
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t t = line.find(time_key);
    const std::size_t f = line.find(file_key);
    if (t == std::string::npos || f == std::string::npos) continue;
    const char* begin = line.data() + t + time_key.size();
    double time = 0.0;
    const auto [end, error] = std::from_chars(begin, line.data() + line.size(), time);
    const std::size_t suffix_begin = f + file_key.size();
    const std::size_t suffix_end = line.find(".vtp", suffix_begin);
    if (error != std::errc() || *end != '"' || suffix_end == std::string::npos) {
      throw std::runtime_error(
          fmt::format("{}: cannot read the snapshot entry '{}'", file.string(), line));
    }
    entries_.emplace_back(time, line.substr(suffix_begin, suffix_end - suffix_begin));
    times.push_back(time);
  }
  return times;
}

void VtkSnapshotSeries::keep_earlier(std::size_t count) {
  entries_.resize(std::min(count, entries_.size()));
  const std::filesystem::path folder = out_dir_ / "snapshots";
  if (std::filesystem::is_directory(folder)) {
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
      const std::string name = entry.path().filename().string();
      const bool kept = std::any_of(entries_.begin(), entries_.end(), [&](const auto& e) {
        return std::any_of(kSnapshotKinds.begin(), kSnapshotKinds.end(), [&](const char* kind) {
          return name == fmt::format("{}_{}.vtp", kind, e.second);
        });
      });
      if (!kept) std::filesystem::remove(entry.path());
    }
  }
  write_collections();
}

void VtkSnapshotSeries::write_collections() const {
  for (const char* kind : kSnapshotKinds) {
    write_file_atomically(out_dir_ / fmt::format("{}.pvd", kind), pvd(entries_, kind));
  }
}

VtkSnapshotSeries::VtkSnapshotSeries(std::filesystem::path out_dir, VtkFormat format)
    : out_dir_(std::move(out_dir)), format_(format) {}

void VtkSnapshotSeries::write(const World& world, const Contacts& contacts) {
  const std::filesystem::path folder = out_dir_ / "snapshots";
  std::filesystem::create_directories(folder);
  const std::string suffix = fmt::format("{:06d}", entries_.size());
  write_file_atomically(folder / fmt::format("particles_{}.vtp", suffix), [&](OutputSink& sink) {
    write_particles_vtp(sink, world, &contacts, format_);
  });
  write_file_atomically(folder / fmt::format("contacts_{}.vtp", suffix), [&](OutputSink& sink) {
    write_contacts_vtp(sink, world, contacts, format_);
  });
  write_file_atomically(folder / fmt::format("walls_{}.vtp", suffix),
                        [&](OutputSink& sink) { write_walls_vtp(sink, world, format_); });
  entries_.emplace_back(world.time, suffix);
  write_collections();
}

}  // namespace cdpowder
