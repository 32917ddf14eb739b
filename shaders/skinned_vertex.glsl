// A skinned scene vertex (`planar::skin::SKINNED_LAYOUT`): the scene's, then JOINTS_0 and
// WEIGHTS_0.
#include "scene_vertex.glsl"
layout(location = 5) in uvec4 in_joints;
layout(location = 6) in vec4 in_weights;
