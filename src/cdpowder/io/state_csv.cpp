// state_csv.cpp — CSV text of spheres and contacts. Numbers use fmt's shortest exact form,
// so re-reading a file gives the same doubles.
#include "cdpowder/io/state_csv.hpp"

#include "cdpowder/contact/contact_view.hpp"
#include "cdpowder/core/index.hpp"

#include <fmt/format.h>

#include <iterator>

namespace cdpowder {

namespace {

void append_vec(std::string& out, const Vec3& v) {
  fmt::format_to(std::back_inserter(out), ",{},{},{}", v.x(), v.y(), v.z());
}

void append_contact(std::string& out, std::int64_t a, std::int64_t b, const Vec3& n,
                    const ContactAction& action, double gap, bool cohesive, double cohesion) {
  fmt::format_to(std::back_inserter(out), "{},{}", a, b);
  append_vec(out, n);
  fmt::format_to(std::back_inserter(out), ",{}", action.normal_force);
  append_vec(out, action.tangential_force);
  append_vec(out, action.rolling_torque);
  const bool closed = is_closed(action.normal_force, cohesion);
  fmt::format_to(std::back_inserter(out), ",{},{},{},{}\n", action.twisting_torque, gap,
                 cohesive ? 1 : 0, closed ? "closed" : "open");
}

}  // namespace

void write_particles_csv(OutputSink& sink, const Bodies& bodies, const std::string& header) {
  ChunkedText chunks(sink);
  std::string& out = chunks.text();
  out = header;
  out += "id,x,y,z,r,vx,vy,vz,wx,wy,wz,fx,fy,fz,tx,ty,tz,fixed\n";
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    fmt::format_to(std::back_inserter(out), "{}", i);
    append_vec(out, bodies.position[i]);
    fmt::format_to(std::back_inserter(out), ",{}", bodies.radius[i]);
    append_vec(out, bodies.velocity[i]);
    append_vec(out, bodies.angular_velocity[i]);
    append_vec(out, bodies.external_force[i]);
    append_vec(out, bodies.external_torque[i]);
    fmt::format_to(std::back_inserter(out), ",{}\n", static_cast<int>(bodies.fixed[i]));
    chunks.chunk_done();
  }
  chunks.finish();
}

std::string particles_csv(const Bodies& bodies, const std::string& header) {
  return written_text([&](OutputSink& sink) { write_particles_csv(sink, bodies, header); });
}

void write_contacts_csv(OutputSink& sink, const Contacts& contacts, const std::string& header) {
  ChunkedText chunks(sink);
  std::string& out = chunks.text();
  out = header;
  out += "a,b,nx,ny,nz,normal_force,tx,ty,tz,rx,ry,rz,twist,gap,cohesive,state\n";
  for_each_contact(contacts, [&](const ContactView& c) {
    // a wall contact's first member is the wall's id
    const std::int64_t first = c.is_pair()                   ? std::int64_t{c.a}
                               : *c.wall == WallKind::Bottom ? kBottomWallId
                                                             : kPistonId;
    append_contact(out, first, c.b, c.normal, *c.action, c.gap, c.cohesive, c.cohesion);
    chunks.chunk_done();
  });
  chunks.finish();
}

std::string contacts_csv(const Contacts& contacts, const std::string& header) {
  return written_text([&](OutputSink& sink) { write_contacts_csv(sink, contacts, header); });
}

}  // namespace cdpowder
