#pragma once
// Scenes with a "damping_design" section (see docs/dynamics.md, "Example-based damping"): the damping
// study of damping_study.hpp configured from JSON and run by `tailor run`, which writes
// DIR/report.json and the plots DIR/envelope.png, DIR/gamma_curve.png, DIR/cycle_loss.png.
#include <iosfwd>
#include <string>

#include "problems/damping_design/damping_study.hpp"

namespace tailor {

class SceneNode;  // problems/scene_node.hpp

// The scene's document ("name" and the "damping_design" section); throws SceneError naming the
// source and key path for bad input (unknown keys included).
DampingStudyOptions parse_damping_design(const SceneNode& root);

// Parses and runs the study, prints a table to `log` when set, writes the outputs into out_dir.
// Returns true when every example mode's measured decay rate is within 5% of its target, every
// other mode's within 5% of plain Rayleigh, and the scheme's own damping below 5% of every target.
bool run_damping_design_scene(const SceneNode& root, const std::string& out_dir, std::ostream* log);

}  // namespace tailor
