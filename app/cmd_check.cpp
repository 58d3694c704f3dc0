// flatmorph check: the G-code safety check (the one every written file passes) on any G-code.
#include <fmt/core.h>

#include <fstream>
#include <sstream>

#include "commands.h"
#include "common/error.h"
#include "gcode/gcode_check.h"
#include "gcode/printer_profile.h"
#include "material/material.h"

namespace flatmorph::cli {
namespace {

struct CheckOptions {
  std::string file;
  std::string printer;
  std::string material = "pla-paper";
};

int run_check(const CheckOptions& options, const GlobalOptions& global) {
  const PrinterProfile printer = load_printer(options.printer);
  const Material material = load_material(options.material);
  std::ifstream in(options.file, std::ios::binary);
  if (!in) {
    throw UserError(ErrorCategory::kFile,
                    fmt::format("{}: cannot open the G-code file; check the path", options.file));
  }
  std::stringstream text;
  text << in.rdbuf();
  const std::vector<GcodeViolation> violations = check_gcode(text.str(), printer, material, 1000);
  for (const GcodeViolation& v : violations) {
    fmt::print("{}:{}: {}: {}\n", options.file, v.line, to_string(v.kind), v.reason);
  }
  if (violations.empty()) {
    if (!global.quiet) {
      fmt::print("{}: safe for {} with {}\n", options.file, printer.name, material.name);
    }
    return 0;
  }
  fmt::print(stderr,
             "flatmorph: error: {} is unsafe for {} with {}: {}{} violation(s), the first "
             "at line {} ({})\n",
             options.file, printer.name, material.name, violations.size(),
             violations.size() >= 1000 ? "+" : "", violations.front().line,
             to_string(violations.front().kind));
  return 2;
}

}  // namespace

Command make_check_command(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<CheckOptions>();
  CLI::App* sub = app.add_subcommand(
      "check",
      "Check that a G-code file is safe to send to a printer: every move on the bed and below "
      "the maximum height, temperatures within the material's limits, no extrusion while "
      "travelling, extrusion distances consistent with M82/M83, heaters and motors off at the "
      "end. Prints one line per violation and exits with status 2 if there is any.");
  sub->add_option("file", options->file, "The G-code file")->required();
  sub->add_option("--printer", options->printer, "Printer preset name or profile JSON file")
      ->required();
  sub->add_option("--material", options->material,
                  "Material preset name or material JSON file (default: pla-paper)");
  return {sub, [options, &global] { return run_check(*options, global); }};
}

}  // namespace flatmorph::cli
