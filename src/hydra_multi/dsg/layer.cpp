#include "hydra_multi/dsg/layer.h"

namespace hydra_multi {

int layerLevel(Layer layer) {
  switch (layer) {
    case Layer::kAgents:
    case Layer::kObjects:
      return 2;
    case Layer::kPlaces:
      return 3;
    case Layer::kRooms:
      return 4;
    case Layer::kBuildings:
      return 5;
  }
  return -1;
}

const char* layerName(Layer layer) {
  switch (layer) {
    case Layer::kAgents:
      return "agents";
    case Layer::kObjects:
      return "objects";
    case Layer::kPlaces:
      return "places";
    case Layer::kRooms:
      return "rooms";
    case Layer::kBuildings:
      return "buildings";
  }
  return "unknown";
}

std::optional<Layer> layerFromName(const std::string& name) {
  for (const Layer layer : kAllLayers) {
    if (name == layerName(layer)) return layer;
  }
  return std::nullopt;
}

char layerCategory(Layer layer) {
  switch (layer) {
    case Layer::kAgents:
      return 'a';
    case Layer::kObjects:
      return 'O';
    case Layer::kPlaces:
      return 'p';
    case Layer::kRooms:
      return 'R';
    case Layer::kBuildings:
      return 'B';
  }
  return '?';
}

bool isValidEdge(Layer a, Layer b) { return a == b || layerLevel(a) != layerLevel(b); }

}  // namespace hydra_multi
