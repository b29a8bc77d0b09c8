#include <gtest/gtest.h>

#include "hydra_multi/frontend/descriptors.h"

namespace hydra_multi {
namespace {

// A chain of places 2 m apart with radii 0.6, 1.0, 1.4, ...; an object under every place; the
// keyframe's parent is the first place.
SceneGraph chain(size_t places) {
  SceneGraph g;
  for (size_t i = 0; i < places; ++i) {
    Node place = makeNode(NodeId('p', i), Layer::kPlaces, Eigen::Vector3d(2.0 * i, 0, 1));
    place.find<PlaceAttributes>()->distance = 0.6 + 0.4 * double(i);
    g.addOrUpdateNode(place);
    if (i > 0) g.addOrUpdateEdge(NodeId('p', i - 1), NodeId('p', i));
    Node object = makeNode(NodeId('O', i), Layer::kObjects, Eigen::Vector3d(2.0 * i, 1, 0));
    object.semantic()->label = 5 + static_cast<uint32_t>(i % 2);
    g.addOrUpdateNode(object);
    g.addOrUpdateEdge(NodeId('p', i), NodeId('O', i));
  }
  g.addOrUpdateNode(makeNode(NodeId('a', 0), Layer::kAgents));
  g.addOrUpdateEdge(NodeId('p', 0), NodeId('a', 0));
  return g;
}

// The neighbourhood stops at the radius along the places graph; histograms are normalized.
TEST(Descriptors, NeighbourhoodAndHistograms) {
  const SceneGraph g = chain(10);
  DescriptorOptions options;
  options.radius = 5.0;  // places 0, 1, 2 (0, 2 and 4 m along the chain)
  KeyframeDescriptor visual;
  visual.bow = {{3, 0.5f}, {9, 0.5f}};
  const KeyframeDescriptors d = describeKeyframe(g, NodeId('a', 0), &visual, options);
  ASSERT_TRUE(d.root.has_value());
  EXPECT_EQ(*d.root, NodeId('p', 0));
  EXPECT_EQ(d.places.size(), 3u);
  EXPECT_EQ(d.objects.size(), 3u);
  // Labels 5, 6, 5.
  ASSERT_EQ(d.object_labels.size(), 2u);
  EXPECT_NEAR(d.object_labels[0].second, 2.0 / 3.0, 1e-12);
  // Radii 0.6, 1.0, 1.4 in bins of (2.5 - 0.5) / 30 m: three bins of a third each.
  EXPECT_EQ(d.place_radii.size(), 3u);
  EXPECT_NEAR(histogramScore(d.place_radii, d.place_radii), 1.0, 1e-12);
  EXPECT_NEAR(histogramScore(d.bow, d.bow), 1.0, 1e-12);
  EXPECT_NEAR(histogramScore(d.bow, {{3, 1.0}}), 0.5, 1e-12);
  EXPECT_NEAR(histogramScore(d.bow, {{4, 1.0}}), 0.0, 1e-12);
  // A keyframe without a parent place has no graph descriptors.
  SceneGraph lonely = g;
  lonely.addOrUpdateNode(makeNode(NodeId('a', 1), Layer::kAgents));
  const KeyframeDescriptors none = describeKeyframe(lonely, NodeId('a', 1), nullptr, options);
  EXPECT_FALSE(none.root.has_value());
  EXPECT_TRUE(none.place_radii.empty() && none.bow.empty());
}

}  // namespace
}  // namespace hydra_multi
