// Issue 9, item 1: every malformed or hostile input of tests/robustness/corpus/ is refused by the
// command line with exit status 2, a one-line reason on stderr that names the input and its error
// category ("flatmorph: error [CATEGORY]: ..."), and no output file. make_corpus.py writes the
// files; fuzz/ adds the inputs its runs found (fuzz_*), which must be refused the same way.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "test_support.h"

namespace flatmorph::corpus_test {
namespace {

namespace fs = std::filesystem;

fs::path corpus_dir() {
  return (fs::path(FLATMORPH_TEST_DATA_DIR) / ".." / "robustness" / "corpus").lexically_normal();
}

struct Case {
  std::string input;              // a file of corpus/ ("" for none)
  std::vector<std::string> args;  // {in}: the corpus file, {out}: a fresh output path
  std::string category;           // as common/error.h's to_string(ErrorCategory) spells it
  std::string names = "";         // what the message must name (default: the input's file name)
};

// Commands that read a mesh and would write files.
std::vector<std::string> flatten(const std::string& extra = "") {
  std::vector<std::string> args = {"flatten", "{in}", "--width", "100", "-o", "{out}"};
  if (!extra.empty()) args.push_back(extra);
  return args;
}
std::vector<std::string> fit() { return {"calibrate", "fit", "{in}", "-o", "{out}.json"}; }

std::vector<Case> cases() {
  std::vector<Case> c = {
      // OBJ
      {"empty.obj", flatten(), "format"},
      {"only_comments.obj", flatten(), "format"},
      {"obj_face_missing_vertex.obj", flatten(), "format"},
      {"obj_face_index_zero.obj", flatten(), "format"},
      {"obj_relative_index_before_start.obj", flatten(), "format"},
      {"obj_two_vertex_face.obj", flatten(), "format"},
      {"obj_truncated_face.obj", flatten(), "format"},
      {"obj_bad_number.obj", flatten(), "format"},
      {"obj_index_overflow.obj", flatten(), "format"},
      {"obj_binary_garbage.obj", flatten(), "format"},
      {"obj_no_faces.obj", flatten(), "geometry"},
      {"obj_nan.obj", flatten(), "geometry"},
      {"obj_inf.obj", flatten(), "geometry"},
      {"obj_1e300.obj", flatten(), "geometry"},
      {"obj_1e-300.obj", flatten(), "geometry"},
      {"obj_all_one_point.obj", flatten(), "geometry"},
      {"obj_collinear_slivers.obj", flatten(), "geometry"},
      {"obj_closed_tetrahedron.obj", flatten(), "topology"},
      {"obj_nonmanifold_edge.obj", flatten(), "topology"},
      {"obj_bowtie_vertex.obj", flatten(), "topology"},
      {"obj_two_components.obj", flatten(), "topology"},
      {"obj_hole.obj", flatten(), "topology"},
      // PLY
      {"empty.ply", flatten(), "format"},
      {"ply_header_only_magic.ply", flatten(), "format"},
      {"ply_no_end_header.ply", flatten(), "format"},
      {"ply_unknown_format.ply", flatten(), "format"},
      {"ply_negative_count.ply", flatten(), "format"},
      {"ply_ascii_truncated.ply", flatten(), "format"},
      {"ply_ascii_face_missing_vertex.ply", flatten(), "format"},
      {"ply_binary_too_few_vertices.ply", flatten(), "format"},
      {"ply_binary_too_many_faces.ply", flatten(), "format"},
      {"ply_binary_truncated.ply", flatten(), "format"},
      {"ply_binary_face_missing_vertex.ply", flatten(), "format"},
      {"ply_binary_negative_index.ply", flatten(), "format"},
      {"ply_claims_6GB.ply", flatten(), "format"},
      {"ply_claims_2G_vertices.ply", flatten(), "format"},
      {"ply_count_overflows_int64.ply", flatten(), "format"},
      {"ply_binary_nan.ply", flatten(), "geometry"},
      {"ply_no_vertex_element.ply", flatten(), "format"},
      {"ply_list_count_255.ply", flatten(), "format"},
      // STL
      {"empty.stl", flatten(), "format"},
      {"stl_binary_claims_4G_triangles.stl", flatten(), "format"},
      {"stl_binary_truncated.stl", flatten(), "format"},
      {"stl_binary_short_header.stl", flatten(), "format"},
      {"stl_binary_inf.stl", flatten(), "geometry"},
      {"stl_ascii_truncated.stl", flatten(), "format"},
      {"stl_ascii_bad_number.stl", flatten(), "format"},
      {"stl_ascii_four_vertices.stl", flatten(), "topology"},
      {"stl_ascii_closed.stl", flatten(), "topology"},
      // OFF
      {"empty.off", flatten(), "format"},
      {"off_binary.off", flatten(), "format"},
      {"off_counts_too_large.off", flatten(), "format"},
      {"off_negative_count.off", flatten(), "format"},
      {"off_truncated.off", flatten(), "format"},
      {"off_face_missing_vertex.off", flatten(), "format"},
      {"off_polygon_of_two.off", flatten(), "format"},
      {"off_huge_polygon_count.off", flatten(), "format"},
      // Not a mesh file at all
      {"mesh.xyz", flatten(), "file"},
      {"no_extension", flatten(), "file"},
      {"",
       {"flatten", "no_such_mesh.obj", "--width", "100", "-o", "{out}"},
       "file",
       "no_such_mesh.obj"},
      {"", {"info", "{corpus}"}, "file", "corpus"},
      // Material JSON
      {"material_not_json.json",
       {"flatten", "--example", "dome", "--width", "100", "--material", "{in}", "-o", "{out}"},
       "profile"},
      {"material_empty.json",
       {"simulate", "{corpus}/plate_grid.ply", "--material", "{in}", "-o", "{out}.ply"},
       "profile"},
      {"material_array.json",
       {"simulate", "{corpus}/plate_grid.ply", "--material", "{in}", "-o", "{out}.ply"},
       "profile"},
      {"material_unknown_key.json",
       {"toolpaths", "{corpus}/plate_grid.ply", "--printer", "generic-marlin", "--material", "{in}",
        "-o", "{out}"},
       "profile"},
      {"material_out_of_range.json",
       {"check", "{corpus}/safe.gcode", "--printer", "generic-marlin", "--material", "{in}"},
       "profile"},
      {"material_wrong_type.json",
       {"check", "{corpus}/safe.gcode", "--printer", "generic-marlin", "--material", "{in}"},
       "profile"},
      {"material_number_overflow.json",
       {"check", "{corpus}/safe.gcode", "--printer", "generic-marlin", "--material", "{in}"},
       "profile"},
      {"material_truncated.json",
       {"check", "{corpus}/safe.gcode", "--printer", "generic-marlin", "--material", "{in}"},
       "profile"},
      {"material_unsafe_temperatures.json",
       {"check", "{corpus}/safe.gcode", "--printer", "generic-marlin", "--material", "{in}"},
       "profile"},
      {"material_deep_nesting.json",
       {"check", "{corpus}/safe.gcode", "--printer", "generic-marlin", "--material", "{in}"},
       "profile"},
      // Printer JSON
      {"printer_not_json.json", {"check", "{corpus}/safe.gcode", "--printer", "{in}"}, "profile"},
      {"printer_empty_object.json",
       {"check", "{corpus}/safe.gcode", "--printer", "{in}"},
       "profile"},
      {"printer_number_overflow.json",
       {"check", "{corpus}/safe.gcode", "--printer", "{in}"},
       "profile"},
      {"printer_truncated.json",
       {"toolpaths", "{corpus}/plate_grid.ply", "--printer", "{in}", "-o", "{out}"},
       "profile"},
      {"printer_string.json",
       {"toolpaths", "{corpus}/plate_grid.ply", "--printer", "{in}", "-o", "{out}"},
       "profile"},
      // Measurement sheets (flatmorph calibrate fit)
      {"csv_empty.csv", fit(), "format"},
      {"csv_no_header.csv", fit(), "format"},
      {"csv_not_a_number.csv", fit(), "format"},
      {"csv_missing_cell.csv", fit(), "format"},
      {"csv_length_grew.csv", fit(), "format"},
      {"csv_nan.csv", fit(), "format"},
      {"csv_wrong_row_count.csv", fit(), "format"},
      {"csv_repeated_sample.csv", fit(), "format"},
      {"csv_binary_garbage.csv", fit(), "format"},
      {"csv_bad_material_line.csv", fit(), "profile"},
      // Plates that are not what flatten writes
      {"plate_no_theta1.ply", {"simulate", "{in}", "-o", "{out}.ply"}, "format"},
      {"plate_nan_theta1.ply",
       {"toolpaths", "{in}", "--printer", "generic-marlin", "-o", "{out}"},
       "format"},
      {"plate_not_flat.ply", {"simulate", "{in}", "-o", "{out}.ply"}, "geometry"},
      // Option values out of range
      {"", {"flatten", "--example", "dome", "--width", "-5", "-o", "{out}"}, "option", "--width"},
      {"", {"flatten", "--example", "dome", "--width", "nan", "-o", "{out}"}, "option", "--width"},
      {"",
       {"flatten", "--example", "dome", "--width", "1e400", "-o", "{out}"},
       "option",
       "--width"},
      {"", {"flatten", "--example", "dome", "--width", "abc", "-o", "{out}"}, "option", "--width"},
      {"",
       {"flatten", "--example", "dome", "--width", "100", "--faces", "0", "-o", "{out}"},
       "option",
       "--faces"},
      {"",
       {"flatten", "--example", "dome", "--width", "100", "--faces", "99999999999", "-o", "{out}"},
       "option",
       "--faces"},
      {"",
       {"flatten", "--example", "dome", "--width", "100", "--wD", "-1", "-o", "{out}"},
       "option",
       "--wD"},
      {"",
       {"flatten", "--example", "no-such-example", "--width", "100", "-o", "{out}"},
       "option",
       "no-such-example"},
      {"",
       {"flatten", "--example", "dome", "--width", "100", "--material", "no-such-material", "-o",
        "{out}"},
       "option",
       "no-such-material"},
      {"",
       {"simulate", "{corpus}/plate_grid.ply", "--layers", "0", "-o", "{out}.ply"},
       "option",
       "--layers"},
      {"",
       {"toolpaths", "{corpus}/plate_grid.ply", "--printer", "generic-marlin", "--layers", "-3",
        "-o", "{out}"},
       "option",
       "--layers"},
      {"",
       {"toolpaths", "{corpus}/plate_grid.ply", "--printer", "generic-marlin", "--spacing", "50",
        "-o", "{out}"},
       "option",
       "--spacing"},
      {"",
       {"toolpaths", "{corpus}/plate_grid.ply", "--printer", "no-such-printer", "-o", "{out}"},
       "option",
       "no-such-printer"},
      {"",
       {"toolpaths", "{corpus}/plate_grid.ply", "--printer", "generic-marlin", "--at", "9999,9999",
        "-o", "{out}"},
       "infeasible",
       "bed"},
      // The output cannot be written where it is asked for
      {"",
       {"flatten", "--example", "dome", "--width", "100", "--faces", "100", "-o",
        "{corpus}/safe.gcode/out"},
       "file",
       "safe.gcode"},
      {"",
       {"toolpaths", "{corpus}/plate_grid.ply", "--printer", "generic-marlin", "-o",
        "{corpus}/safe.gcode/out"},
       "file",
       "safe.gcode"},
  };
  // Crash and hang inputs found by the fuzz targets (fuzz/README.md): whatever the reader, a
  // format error or a refusal of the mesh.
  for (const auto& entry : fs::directory_iterator(corpus_dir())) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("fuzz_", 0) != 0) continue;
    const std::string ext = entry.path().extension().string();
    if (ext == ".json" && name.rfind("fuzz_material", 0) == 0) {
      c.push_back(
          {name,
           {"check", "{corpus}/safe.gcode", "--printer", "generic-marlin", "--material", "{in}"},
           "profile"});
    } else if (ext == ".csv") {
      c.push_back({name, fit(), "format"});
    } else if (ext == ".json") {
      c.push_back({name, {"check", "{corpus}/safe.gcode", "--printer", "{in}"}, "profile"});
    } else {
      c.push_back({name, flatten(), ""});
    }
  }
  return c;
}

std::string substitute(std::string arg, const std::string& key, const std::string& value) {
  for (size_t at = arg.find(key); at != std::string::npos; at = arg.find(key, at + value.size())) {
    arg.replace(at, key.size(), value);
  }
  return arg;
}

TEST(Robustness, EveryHostileInputIsRefusedWithOneLineAndNoOutput) {
  const std::vector<Case> all = cases();
  const fs::path scratch = testing::scratch_dir();
  std::set<std::string> inputs;
  int index = 0;
  for (const Case& c : all) {
    std::string trace = c.input;
    for (const std::string& a : c.args) trace += " " + a;
    SCOPED_TRACE(trace);
    if (!c.input.empty()) {
      ASSERT_TRUE(fs::exists(corpus_dir() / c.input)) << "missing corpus file";
      inputs.insert(c.input);
    }
    // Each case writes (if it wrongly writes anything) into a folder of its own.
    const fs::path case_dir = scratch / std::to_string(index++);
    fs::create_directories(case_dir);
    std::vector<std::string> args;
    for (const std::string& a : c.args) {
      std::string s = substitute(a, "{in}", (corpus_dir() / c.input).string());
      s = substitute(s, "{out}", (case_dir / "out").string());
      args.push_back(substitute(s, "{corpus}", corpus_dir().string()));
    }
    const testing::CliResult r = testing::run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("flatmorph: error [", 0), 0u) << r.err;
    if (!c.category.empty()) {
      EXPECT_NE(r.err.find("flatmorph: error [" + c.category + "]: "), std::string::npos) << r.err;
    }
    const std::string names = c.names.empty() ? c.input : c.names;
    EXPECT_NE(r.err.find(names), std::string::npos)
        << "the message does not name " << names << ": " << r.err;
    EXPECT_TRUE(fs::is_empty(case_dir)) << "an output was written";
  }
  EXPECT_GE(inputs.size(), 40u);
  // Every file of the corpus is used by a case (safe.gcode and plate_grid.ply are the good inputs
  // next to a bad one).
  for (const auto& entry : fs::directory_iterator(corpus_dir())) {
    const std::string name = entry.path().filename().string();
    if (name == "safe.gcode" || name == "plate_grid.ply") continue;
    EXPECT_TRUE(inputs.count(name)) << name << " is in the corpus but no case uses it";
  }
}

}  // namespace
}  // namespace flatmorph::corpus_test
