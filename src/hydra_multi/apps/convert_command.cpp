// `hydra-multi convert IN OUT`: between our JSON, Spark-DSG JSON and our binary; PLY for the mesh.

#include <filesystem>
#include <iostream>
#include <map>

#include "hydra_multi/apps/commands.h"
#include "hydra_multi/dsg/io/graph_file.h"

namespace hydra_multi::apps {

int fail(const std::string& message) {
  std::cerr << "hydra-multi: error: " << message << "\n";
  return 1;
}

int runConvert(const ConvertOptions& options) {
  const auto out_format = io::formatFromPath(options.output);
  if (!out_format) {
    return fail(options.output + ": unknown extension (.json, .spark.json, .dsgb or .ply)");
  }
  std::map<std::string, size_t> unread;
  auto graph = io::loadSceneGraph(options.input, &unread);
  if (!graph) return fail(graph.error());
  if (!unread.empty())
    std::cerr << "hydra-multi: note: " << io::describeUnread(options.input, unread) << "\n";
  if (*out_format == io::FileFormat::kPly && graph.value().mesh().empty()) {
    std::cerr << "hydra-multi: warning: " << options.input
              << " has no mesh; the PLY file holds no vertices\n";
  }
  if (*out_format == io::FileFormat::kSparkJson && !graph.value().mesh().empty()) {
    std::cerr << "hydra-multi: warning: the Spark-DSG JSON layout holds no mesh; "
              << graph.value().mesh().vertices.size() << " mesh vertices are left out\n";
  }
  if (Status status = io::saveSceneGraph(options.output, graph.value()); !status) {
    return fail(status.message());
  }
  std::cout << "wrote " << options.output << " (" << io::formatName(*out_format) << ", "
            << std::filesystem::file_size(options.output) << " bytes)\n";
  return 0;
}

}  // namespace hydra_multi::apps
