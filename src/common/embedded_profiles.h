// The preset files shipped in profiles/ (printers/*.json and materials/*.json), compiled into the
// program at build time (src/embed_profiles.cmake) so that build/flatmorph finds them from any
// working directory.
#pragma once

#include <span>
#include <string_view>

namespace flatmorph {

struct EmbeddedProfile {
  std::string_view kind;  // "printers" or "materials": the folder under profiles/
  std::string_view name;  // the file name without .json: the name users select the preset by
  std::string_view text;  // the JSON text of the file
};

// Every shipped preset, sorted by kind then name.
std::span<const EmbeddedProfile> embedded_profiles();

}  // namespace flatmorph
