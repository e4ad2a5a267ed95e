// vtk.cpp — writing .vtp and .pvd documents with fmt (VTK XML file format, PolyData).
#include "cdpowder/io/vtk.hpp"

#include "cdpowder/analysis/coordination.hpp"
#include "cdpowder/io/atomic_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <stdexcept>

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

void begin_polydata(Buffer& out, std::size_t points, std::size_t verts, std::size_t lines,
                    std::size_t polys = 0) {
  fmt::format_to(std::back_inserter(out),
                 "<?xml version=\"1.0\"?>\n"
                 "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
                 "header_type=\"UInt64\">\n"
                 "<PolyData>\n"
                 "<Piece NumberOfPoints=\"{}\" NumberOfVerts=\"{}\" NumberOfLines=\"{}\" "
                 "NumberOfStrips=\"0\" NumberOfPolys=\"{}\">\n",
                 points, verts, lines, polys);
}

void end_polydata(Buffer& out) {
  fmt::format_to(std::back_inserter(out), "</Piece>\n</PolyData>\n</VTKFile>\n");
}

/// <DataArray> with the values produced by value(i) for i < count, `components` each.
template <typename ValueOf>
void data_array(Buffer& out, const char* type, const char* name, int components, std::size_t count,
                ValueOf&& value) {
  fmt::format_to(std::back_inserter(out),
                 "<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" "
                 "format=\"ascii\">\n",
                 type, name, components);
  for (std::size_t i = 0; i < count; ++i) value(out, i);
  fmt::format_to(std::back_inserter(out), "</DataArray>\n");
}

void put_vec(Buffer& out, const Vec3& v) {
  fmt::format_to(std::back_inserter(out), "{:.9g} {:.9g} {:.9g}\n", v.x(), v.y(), v.z());
}

/// Connectivity and offsets of `cells` cells of `size` consecutive points each, the first
/// at point `first_point`.
void cell_arrays(Buffer& out, const char* section, std::size_t cells, std::size_t size,
                 std::size_t first_point = 0) {
  fmt::format_to(std::back_inserter(out), "<{}>\n", section);
  data_array(out, "Int64", "connectivity", 1, cells * size,
             [first_point](Buffer& b, std::size_t i) {
               fmt::format_to(std::back_inserter(b), "{}\n", first_point + i);
             });
  data_array(out, "Int64", "offsets", 1, cells, [size](Buffer& b, std::size_t i) {
    fmt::format_to(std::back_inserter(b), "{}\n", (i + 1) * size);
  });
  fmt::format_to(std::back_inserter(out), "</{}>\n", section);
}

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
};

std::vector<NetworkLine> network_lines(const World& world, const Contacts& contacts) {
  std::vector<NetworkLine> lines;
  const Bodies& bodies = world.bodies;
  for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
    const PairProblem& p = contacts.pairs[k];
    const ContactAction& action = contacts.pair_actions[k];
    // open contacts are left out; a force that is not a number is drawn (a failed state)
    if (!is_closed(action.normal_force, p.cohesion) && !std::isnan(action.normal_force)) continue;
    const Vec3& a = bodies.position[p.a];
    const Vec3 b = a + world.box.minimum_image(bodies.position[p.b] - a);
    lines.push_back({a, b, p.normal, action.normal_force * p.normal + action.tangential_force,
                     action.normal_force, action.tangential_force.norm(),
                     contacts.pair_cohesive[k] != 0, kKindPair});
  }
  for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
    const WallProblem& w = contacts.walls[k];
    const ContactAction& action = contacts.wall_actions[k];
    if (!is_closed(action.normal_force, w.cohesion) && !std::isnan(action.normal_force)) continue;
    const Vec3& centre = bodies.position[w.sphere];
    // n points from the wall into the sphere: the contact point is R behind the centre
    lines.push_back({centre, centre - w.radius * w.normal, w.normal,
                     action.normal_force * w.normal + action.tangential_force, action.normal_force,
                     action.tangential_force.norm(), contacts.wall_cohesive[k] != 0,
                     w.wall == WallKind::Bottom ? kKindBottom : kKindPiston});
  }
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

std::string particles_vtp(const World& world, const Contacts* contacts) {
  const Bodies& bodies = world.bodies;
  const std::size_t n = bodies.size();
  const std::vector<int> coordination =
      contacts != nullptr ? contacts_per_sphere(*contacts, n) : std::vector<int>{};
  Buffer out;
  begin_polydata(out, n, n, 0);
  fmt::format_to(std::back_inserter(out), "<Points>\n");
  data_array(out, "Float64", "Points", 3, n,
             [&](Buffer& b, std::size_t i) { put_vec(b, bodies.position[i]); });
  fmt::format_to(std::back_inserter(out), "</Points>\n");
  cell_arrays(out, "Verts", n, 1);
  fmt::format_to(std::back_inserter(out), "<PointData Scalars=\"radius\" Vectors=\"velocity\">\n");
  data_array(out, "Int64", "id", 1, n,
             [](Buffer& b, std::size_t i) { fmt::format_to(std::back_inserter(b), "{}\n", i); });
  data_array(out, "Float64", "radius", 1, n, [&](Buffer& b, std::size_t i) {
    fmt::format_to(std::back_inserter(b), "{:.9g}\n", bodies.radius[i]);
  });
  data_array(out, "Float64", "velocity", 3, n,
             [&](Buffer& b, std::size_t i) { put_vec(b, bodies.velocity[i]); });
  data_array(out, "Float64", "angular_velocity", 3, n,
             [&](Buffer& b, std::size_t i) { put_vec(b, bodies.angular_velocity[i]); });
  if (contacts != nullptr) {
    data_array(out, "Int32", "coordination", 1, n, [&](Buffer& b, std::size_t i) {
      fmt::format_to(std::back_inserter(b), "{}\n", coordination[i]);
    });
  }
  fmt::format_to(std::back_inserter(out), "</PointData>\n");
  end_polydata(out);
  return fmt::to_string(out);
}

std::string contacts_vtp(const World& world, const Contacts& contacts) {
  const std::vector<NetworkLine> lines = network_lines(world, contacts);
  const std::size_t n = lines.size();
  Buffer out;
  begin_polydata(out, 2 * n, 0, n);
  fmt::format_to(std::back_inserter(out), "<Points>\n");
  data_array(out, "Float64", "Points", 3, 2 * n, [&](Buffer& b, std::size_t i) {
    put_vec(b, i % 2 == 0 ? lines[i / 2].from : lines[i / 2].to);
  });
  fmt::format_to(std::back_inserter(out), "</Points>\n");
  cell_arrays(out, "Lines", n, 2);
  fmt::format_to(std::back_inserter(out),
                 "<CellData Scalars=\"normal_force\" Vectors=\"force\" Normals=\"normal\">\n");
  data_array(out, "Float64", "normal_force", 1, n, [&](Buffer& b, std::size_t i) {
    fmt::format_to(std::back_inserter(b), "{:.9g}\n", lines[i].normal_force);
  });
  data_array(out, "Float64", "force", 3, n,
             [&](Buffer& b, std::size_t i) { put_vec(b, lines[i].force); });
  data_array(out, "Float64", "normal", 3, n,
             [&](Buffer& b, std::size_t i) { put_vec(b, lines[i].normal); });
  data_array(out, "Int32", "tensile", 1, n, [&](Buffer& b, std::size_t i) {
    fmt::format_to(std::back_inserter(b), "{}\n", lines[i].normal_force < 0.0 ? 1 : 0);
  });
  data_array(out, "Float64", "tangential_force", 1, n, [&](Buffer& b, std::size_t i) {
    fmt::format_to(std::back_inserter(b), "{:.9g}\n", lines[i].tangential_force);
  });
  data_array(out, "Int32", "cohesive", 1, n, [&](Buffer& b, std::size_t i) {
    fmt::format_to(std::back_inserter(b), "{}\n", lines[i].cohesive ? 1 : 0);
  });
  data_array(out, "Int32", "kind", 1, n, [&](Buffer& b, std::size_t i) {
    fmt::format_to(std::back_inserter(b), "{}\n", lines[i].kind);
  });
  fmt::format_to(std::back_inserter(out), "</CellData>\n");
  end_polydata(out);
  return fmt::to_string(out);
}

std::string walls_vtp(const World& world) {
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
  std::vector<Vec3> points;
  for (const auto& [x, y] : {std::pair{0.0, 0.0}, {lx, 0.0}, {lx, ly}, {0.0, ly}}) {
    points.emplace_back(x, y, 0.0);
    points.emplace_back(x, y, top);
  }
  std::vector<int> kinds(4, kWallsKindCellEdge);  // cell data: the lines first, then the polys
  const auto add_plane = [&](double z, int kind) {
    for (const auto& [x, y] : {std::pair{0.0, 0.0}, {lx, 0.0}, {lx, ly}, {0.0, ly}}) {
      points.emplace_back(x, y, z);
    }
    kinds.push_back(kind);
  };
  if (walls.bottom.enabled) add_plane(0.0, kWallsKindBottom);
  if (walls.piston.enabled) add_plane(walls.piston.height, kWallsKindPiston);
  const std::size_t planes = kinds.size() - 4;
  Buffer out;
  begin_polydata(out, points.size(), 0, 4, planes);
  fmt::format_to(std::back_inserter(out), "<Points>\n");
  data_array(out, "Float64", "Points", 3, points.size(),
             [&](Buffer& b, std::size_t i) { put_vec(b, points[i]); });
  fmt::format_to(std::back_inserter(out), "</Points>\n");
  cell_arrays(out, "Lines", 4, 2);
  cell_arrays(out, "Polys", planes, 4, 8);
  fmt::format_to(std::back_inserter(out), "<CellData Scalars=\"kind\">\n");
  data_array(out, "Int32", "kind", 1, kinds.size(), [&](Buffer& b, std::size_t i) {
    fmt::format_to(std::back_inserter(b), "{}\n", kinds[i]);
  });
  fmt::format_to(std::back_inserter(out), "</CellData>\n");
  end_polydata(out);
  return fmt::to_string(out);
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

VtkSnapshotSeries::VtkSnapshotSeries(std::filesystem::path out_dir)
    : out_dir_(std::move(out_dir)) {}

void VtkSnapshotSeries::write(const World& world, const Contacts& contacts) {
  const std::filesystem::path folder = out_dir_ / "snapshots";
  std::filesystem::create_directories(folder);
  const std::string suffix = fmt::format("{:06d}", entries_.size());
  write_file_atomically(folder / fmt::format("particles_{}.vtp", suffix),
                        particles_vtp(world, &contacts));
  write_file_atomically(folder / fmt::format("contacts_{}.vtp", suffix),
                        contacts_vtp(world, contacts));
  write_file_atomically(folder / fmt::format("walls_{}.vtp", suffix), walls_vtp(world));
  entries_.emplace_back(world.time, suffix);
  write_collections();
}

}  // namespace cdpowder
