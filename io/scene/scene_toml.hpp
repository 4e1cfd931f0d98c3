#pragma once
// Loading a scene file into a TOML table and applying command-line overrides to it.
//
// Override syntax (ifsim run --set KEY=VALUE): KEY is a dotted path; a number in the path picks
// an entry of an array counted from 1, like the stage column of history.csv
// (stage.2.deps_11 is deps_11 of the second [[stage]]; initial.stress.1 is the first stress
// component). VALUE is read as a TOML value (number, string, boolean, array, inline table);
// a bare word that is no TOML value is taken as a string (model=sanisand). Missing tables on
// the way are created, so optional sections can be set; whether the key itself is known is
// checked by the scene reader afterwards, like every key of the file.

#include <string>
#include <string_view>

#include <toml++/toml.h>

namespace ifsim::io {

// Name of the TOML source of values given with --set (their nodes carry it as source path).
inline constexpr std::string_view override_source = "--set";

// Parses the scene file. Throws SceneError (file missing, unreadable, or not valid TOML with
// the line and column of the problem).
toml::table load_scene_table(const std::string& file);

// The same for a scene's text (`file` names it in messages and is its source path).
toml::table parse_scene_text(std::string_view text, const std::string& file);

// Applies one "KEY=VALUE" override to the scene. Throws SceneError naming the file and KEY.
void apply_override(toml::table& scene, std::string_view assignment, const std::string& file);

// The key part of an assignment ("material.roughness" of "material.roughness=0.5").
std::string override_key(std::string_view assignment);

// The scene's kind (required string). Throws SceneError.
std::string scene_kind(const toml::table& scene, const std::string& file);

} // namespace ifsim::io
