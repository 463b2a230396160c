#pragma once
// The [settings] table of a scene file, for the host-only files that read their app's keys
// (toml++ cannot be compiled by nvcc, so only host-only translation units include this).
#include <toml++/toml.h>

#include <initializer_list>
#include <string>
#include <string_view>

#include "rtmini/io/scene_file.hpp"

namespace rtmini {

struct SceneSettings {
  toml::table table;
};

// Every key of `table` must be in `known`, else InputError
// "file:line: unknown key 'foo' in [where]".
void check_known_keys(const toml::table& table, std::initializer_list<std::string_view> known,
                      const std::string& file, const std::string& where);

}  // namespace rtmini
