// hydra-multi: the command line. It only parses options into the commands' option structs.

#include <CLI/CLI.hpp>
#include <string>

#include "hydra_multi/apps/commands.h"
#include "hydra_multi/core/version.h"

int main(int argc, char** argv) {
  using namespace hydra_multi::apps;
  CLI::App app{
      "hydra-multi: one 3D scene graph of a building from a team of robots (Hydra-Multi).\n"
      "File formats, chosen by extension: .json (ours), .spark.json (Spark-DSG), .dsgb (binary),\n"
      ".ply (mesh, write only). A .json file in Spark-DSG's layout is recognised by its content."};
  app.set_version_flag("--version", std::string("hydra-multi ") + hydra_multi::kVersion);
  app.require_subcommand(1);

  InfoOptions info;
  CLI::App* info_cmd = app.add_subcommand(
      "info", "Counts per layer and per robot of a scene graph or update stream");
  info_cmd
      ->add_option("file", info.path, "scene graph (.json, .spark.json, .dsgb) or update stream")
      ->required()
      ->check(CLI::ExistingFile);
  info_cmd->add_flag("--json", info.json, "print exactly one JSON object on stdout");

  ConvertOptions convert;
  CLI::App* convert_cmd =
      app.add_subcommand("convert", "Convert a scene graph between formats (by extension)");
  convert_cmd->add_option("input", convert.input, "input graph (.json, .spark.json, .dsgb)")
      ->required()
      ->check(CLI::ExistingFile);
  convert_cmd->add_option("output", convert.output, "output (.json, .spark.json, .dsgb, .ply)")
      ->required();

  CLI11_PARSE(app, argc, argv);
  if (*info_cmd) return runInfo(info);
  if (*convert_cmd) return runConvert(convert);
  return 0;
}
