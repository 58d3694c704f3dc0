// libFuzzer target for material JSON files (load_material): any bytes give a Material or a
// UserError, nothing else. load_material reads files only, so each input goes through a
// temporary file of this process.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/error.h"
#include "material/material.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace flatmorph;
  static const std::string path =
      (std::filesystem::temp_directory_path() /
       ("flatmorph-fuzz-material-" + std::to_string(::getpid()) + ".json"))
          .string();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    load_material(path);
  } catch (const UserError&) {
  }
  return 0;
}
