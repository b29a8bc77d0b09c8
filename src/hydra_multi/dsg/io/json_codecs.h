#pragma once
// JSON codecs of the parts our documents share: nodes, edges, mesh vertices and faces, poses and
// information matrices (json_format.h describes the layout). Readers throw DecodeError naming the
// key; the document readers add the item and turn it into an Error.

#include <vector>

#include "hydra_multi/dsg/io/json_fields.h"
#include "hydra_multi/dsg/robot_update.h"

namespace hydra_multi::io {

Json vec3(const Eigen::Vector3d& v);
/// Floats written with their shortest exact digits (floatForJson).
Json vec3f(const Eigen::Vector3f& v);
Json nodesJson(const std::vector<Node>& nodes);
Json edgesJson(const std::vector<Edge>& edges);
Json verticesJson(const std::vector<MeshVertex>& vertices);
Json facesJson(const std::vector<MeshFace>& faces);
Json poseJson(const Eigen::Isometry3d& T);
Json informationJson(const Matrix6d& info);

Node readNode(const Json& j);
Edge readEdge(const Json& j);
MeshVertex readVertex(const Json& j);
MeshFace readFace(const Json& j);
EdgeKey readEdgeKey(const Json& j);
Eigen::Isometry3d readPose(const Json& j, const char* key);
Matrix6d readInformation(const Json& j);

}  // namespace hydra_multi::io
