// flatmorph help [COMMAND...] [--markdown]: a command's help, or the whole command reference as
// Markdown (docs/cli.md's generated part). Both come from the option definitions --help prints,
// so the reference cannot drift from the program (a test compares docs/cli.md with this output).
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "commands.h"
#include "common/error.h"

namespace flatmorph::cli {
namespace {

struct HelpOptions {
  std::vector<std::string> command;
  bool markdown = false;
};

// Text in a Markdown table cell: one line, no column breaks.
std::string cell(std::string text) {
  std::string out;
  for (char c : text) {
    if (c == '|') {
      out += "\\|";
    } else {
      out += c == '\n' ? ' ' : c;
    }
  }
  return out;
}

bool is_help(const CLI::Option* option) {
  const std::string name = option->get_name(false, true);
  return name == "-h,--help" || name == "--help" || name == "--help-all" || name == "--version";
}

// "--no-gcode{false}" names the flag as typed.
std::string option_names(const CLI::Option* option) {
  std::string names = option->get_name(true, true);
  std::string out;
  bool in_braces = false;
  for (char c : names) {
    if (c == '{') in_braces = true;
    if (!in_braces) out += c == ',' ? std::string(", ") : std::string(1, c);
    if (c == '}') in_braces = false;
  }
  return out;
}

void markdown_options(const CLI::App& app, std::string& out) {
  const std::vector<const CLI::Option*> options =
      app.get_options([](const CLI::Option* o) { return !is_help(o) && !o->get_group().empty(); });
  if (options.empty()) return;
  out += "| argument or option | value | default | meaning |\n| --- | --- | --- | --- |\n";
  for (const CLI::Option* o : options) {
    const bool flag = o->get_items_expected_max() == 0;
    const std::string value = flag ? "" : o->get_type_name();
    const std::string fallback = o->get_required() ? "required" : o->get_default_str();
    out += fmt::format("| `{}` | {} | {} | {} |\n", option_names(o), cell(value), cell(fallback),
                       cell(o->get_description()));
  }
}

void markdown_command(const CLI::App& app, const std::string& prefix, std::string& out) {
  const std::string name = prefix + " " + app.get_name();
  out += fmt::format("\n## `{}`\n\n{}\n\n", name, app.get_description());
  markdown_options(app, out);
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    markdown_command(*sub, name, out);
  }
}

std::string markdown_reference(const CLI::App& root) {
  std::string out = "## Options for every command\n\n";
  markdown_options(root, out);
  for (const CLI::App* sub : root.get_subcommands([](const CLI::App*) { return true; })) {
    markdown_command(*sub, "flatmorph", out);
  }
  return out;
}

int run_help(const HelpOptions& options, const CLI::App& root) {
  if (options.markdown) {
    if (!options.command.empty()) {
      throw UserError(ErrorCategory::kOption,
                      "--markdown prints the whole reference: give no command with it");
    }
    fmt::print("{}", markdown_reference(root));
    return 0;
  }
  const CLI::App* app = &root;
  std::string usage = root.get_name();  // the usage line's "flatmorph calibrate fit"
  for (const std::string& name : options.command) {
    const std::vector<const CLI::App*> found =
        app->get_subcommands([&](const CLI::App* sub) { return sub->get_name() == name; });
    if (found.empty()) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("no command '{}': 'flatmorph --help' lists them", name));
    }
    app = found.front();
    usage += " " + app->get_name();
  }
  // App::help would show the help command's own help: it follows the parsed subcommand.
  fmt::print("{}", app->get_formatter()->make_help(app, usage, CLI::AppFormatMode::Normal));
  return 0;
}

}  // namespace

Command make_help_command(CLI::App& app, const GlobalOptions&) {
  auto options = std::make_shared<HelpOptions>();
  CLI::App* sub = app.add_subcommand(
      "help",
      "The help of a command (flatmorph help design is flatmorph design --help), or with "
      "--markdown the whole command reference as Markdown, as docs/cli.md holds it.");
  sub->add_option("command", options->command, "The command, and its subcommand if it has one");
  sub->add_flag("--markdown", options->markdown, "Print every command's options as Markdown");
  return {sub, [options, &app] { return run_help(*options, app); }};
}

}  // namespace flatmorph::cli
