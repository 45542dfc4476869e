#pragma once
// A hanging chain of interlocked tori (docs/tori.md): link k (k = 0 .. count-1) centred at
// (0, 0, -k spacing), even links in the xz plane, odd links in the yz plane (alternating 90
// degrees), the whole chain then tilted by `tilt` about the x axis through link 0's centre.
// Neighbouring core circles are 2R - spacing apart (each passes through the other's hole), so
// R < spacing < 2 (R - r) keeps them interlocked and every pair apart at the start (checked).
#include <string>
#include <vector>

#include "forward/rigid/rigid_body_system.hpp"
#include "forward/tori/torus.hpp"

namespace tailor::tori {

struct ChainSpec {
  int count = 5;
  TorusShape shape;
  double spacing = 0.0;  // 0: 2 (R - r) - gap
  double gap = 1e-3;     // the start's gap between neighbours when spacing = 0 [length]
  double density = 1000.0;
  double tilt = 0.0;               // [rad]
  bool fix_first = true;
  int major_segments = 48, minor_segments = 12;  // the bodies' meshes (output, checks)
  bool inscribed = true;  // meshes inside the implicit tori (torus.hpp)
  double effective_spacing() const;
};

struct Chain {
  std::vector<rigid::RigidBody> bodies;
  std::vector<TorusShape> shapes;
};

// Throws std::invalid_argument (naming `where`) on count < 2, a bad shape, a non-positive
// density, or a spacing that does not keep neighbours interlocked and apart.
Chain make_chain(const ChainSpec& spec, const std::string& where = "chain");

}  // namespace tailor::tori
