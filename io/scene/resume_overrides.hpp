#pragma once
// Which scene keys `ifsim resume DIR --set KEY=VALUE` may change. DIR/checkpoint holds a state
// made with the mesh, the materials, the stages and each pair's model; those stay. What may
// change is how the equations are solved: the [solver] table and a pair's solution controls
// (Algorithm 1's tolerances and Jacobians, the contact Jacobian, the slip viscosity). A run so
// resumed is no longer the uninterrupted run: its scene copy and summary say so.

#include <span>
#include <string>
#include <string_view>

namespace ifsim::io {

// The keys of an [[contact]] or [interface] table a resumed run may change.
std::span<const std::string_view> resumable_contact_keys();

// Empty when `assignment` (KEY=VALUE, as given to --set) may change in a resumed
// boundary-value run; else why not, naming the key.
std::string resume_override_refusal(std::string_view assignment);

} // namespace ifsim::io
