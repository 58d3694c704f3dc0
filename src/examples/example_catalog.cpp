#include "examples/example_catalog.h"

#include "examples/examples.h"
#include "examples/height_field_examples.h"
#include "examples/origami_examples.h"
#include "examples/tile_examples.h"

namespace flatmorph {

std::vector<ExampleEntry> example_catalog() {
  std::vector<ExampleEntry> catalog;
  for (const ExampleInfo& info : example_list()) {
    catalog.push_back({"shrink_morph", "design", info.name, info.description});
  }
  for (const ExampleInfo& info : height_field_example_list()) {
    catalog.push_back({"heightfield", "heightfield", info.name, info.description});
  }
  for (const ExampleInfo& info : tile_example_list()) {
    catalog.push_back({"tiles", "tiles", info.name, info.description});
  }
  for (const ExampleInfo& info : origami_example_list()) {
    catalog.push_back({"origami", "origami", info.name, info.description});
  }
  return catalog;
}

std::vector<std::string> example_names(std::string_view method) {
  std::vector<std::string> names;
  for (const ExampleEntry& entry : example_catalog()) {
    if (entry.method == method) names.push_back(entry.name);
  }
  return names;
}

}  // namespace flatmorph
