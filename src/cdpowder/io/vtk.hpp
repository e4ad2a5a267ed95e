// vtk.hpp — VTK XML PolyData (.vtp) files that ParaView opens, and .pvd collections of
// them over time. ASCII, readable and diffable (a 100 000-sphere snapshot is ≈ 15 MB), binary
// (VtkFormat::Binary: appended base64 at full precision) or zlib (VtkFormat::Zlib: appended raw
// binary compressed in vtkZLibDataCompressor's layout). The run's folder resolves
// VtkFormat::Auto by the sphere count (vtk_format_for, config/scene.hpp); here it is ASCII.
// Every file is written atomically (io/atomic_file.hpp).
//
// Particles: one point per sphere (a vertex cell each) with point data id, radius [R],
// velocity [R/t0], angular_velocity [1/t0], coordination (closed contacts incl. walls).
// Render with the Glyph filter, sphere glyphs scaled by "radius" with a scale factor of 2
// (ParaView's sphere glyph has radius 0.5; README, "In ParaView").
//
// Contact network: one line per closed contact (R_n + F_c > 0), from the centre of a to
// the centre of b's periodic image nearest to a (so lines never span the cell), or, for a
// wall contact, from the sphere centre to its contact point on the wall. Cell data:
// normal_force R_n [F_coh] (> 0 compressive), force R_n n + R_t (a vector: the force on b, or
// on the sphere of a wall contact) [F_coh], normal n (unit, from a to b, or from the wall into
// the sphere), tensile (1 if R_n < 0), tangential_force |R_t| [F_coh], cohesive (0/1), kind
// (0 sphere–sphere, 1 bottom wall, 2 piston).
//
// Walls: the periodic cell's four vertical edges as lines (up to the piston, or to the highest
// sphere top without one), then the bottom wall (z = 0) and the piston (z = Z_P) as squares
// over the cell, each only when it is enabled. Cell data: kind (0 bottom wall, 1 piston, 2 an
// edge of the cell).
#pragma once

#include "cdpowder/config/scene.hpp"
#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/io/output_sink.hpp"
#include "cdpowder/model/world.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace cdpowder {

/// The particles of `world` as a .vtp document; coordination from `contacts`, or no
/// coordination array when `contacts` is null (a deposit, whose contacts are not detected).
/// The write_ forms hand the document to `sink` as it is made (the binary forms' appended
/// data, compressed or base64, at the end); the others return it.
void write_particles_vtp(OutputSink& sink, const World& world, const Contacts* contacts,
                         VtkFormat format = VtkFormat::Ascii);
std::string particles_vtp(const World& world, const Contacts* contacts,
                          VtkFormat format = VtkFormat::Ascii);

/// The closed contacts of `contacts` as a .vtp document of lines.
void write_contacts_vtp(OutputSink& sink, const World& world, const Contacts& contacts,
                        VtkFormat format = VtkFormat::Ascii);
std::string contacts_vtp(const World& world, const Contacts& contacts,
                         VtkFormat format = VtkFormat::Ascii);

/// The pieces of an MPI job (VTK's parallel convention, which ParaView opens as one data set):
/// rank r writes the spheres with sphere_rank[i] == r to particles/particles_r.vtp (their `id`
/// names them) and the closed contacts of its spheres (a pair's first sphere, a wall contact's
/// sphere) to contacts/contacts_r.vtp; rank 0 writes particles.pvtp and contacts.pvtp, which
/// name the `pieces` files and declare their arrays. The pieces together hold the points and
/// lines of particles.vtp and contacts.vtp, in another order.
void write_particles_piece(OutputSink& sink, const World& world, const Contacts* contacts,
                           const std::vector<int>& sphere_rank, int rank,
                           VtkFormat format = VtkFormat::Ascii);
void write_contacts_piece(OutputSink& sink, const World& world, const Contacts& contacts,
                          const std::vector<int>& sphere_rank, int rank,
                          VtkFormat format = VtkFormat::Ascii);
std::string particles_pvtp(int pieces, bool with_coordination);
std::string contacts_pvtp(int pieces);

/// The bottom wall, the piston and the periodic cell of `world` as a .vtp document.
void write_walls_vtp(OutputSink& sink, const World& world, VtkFormat format = VtkFormat::Ascii);
std::string walls_vtp(const World& world, VtkFormat format = VtkFormat::Ascii);

/// A time series of snapshots: DIR/snapshots/{particles,contacts,walls}_NNNNNN.vtp and the
/// collections DIR/particles.pvd, DIR/contacts.pvd and DIR/walls.pvd, rewritten (atomically)
/// after every snapshot so a run that is stopped early still leaves valid collections.
class VtkSnapshotSeries {
 public:
  explicit VtkSnapshotSeries(std::filesystem::path out_dir, VtkFormat format = VtkFormat::Ascii);

  /// Writes the snapshot of the current state, labelled with world.time.
  void write(const World& world, const Contacts& contacts);

  /// Continues the series an earlier process wrote into the folder (a run continued from a
  /// checkpoint): reads its particles.pvd and returns the times of its snapshots, in order.
  /// No file: none. Throws std::runtime_error for a collection it cannot read.
  std::vector<double> read_earlier();

  /// Keeps the first `count` snapshots read by read_earlier(): the files of later ones (and
  /// any file a killed process wrote beyond its collection) are removed and the collections
  /// rewritten.
  void keep_earlier(std::size_t count);

 private:
  /// Rewrites the three collections from entries_.
  void write_collections() const;

  std::filesystem::path out_dir_;
  VtkFormat format_;
  std::vector<std::pair<double, std::string>> entries_;  ///< (time, file stem suffix)
};

}  // namespace cdpowder
