// The shadow techniques' vertex (`shadow_atlas::passes::ATLAS_VERTEX`): position, normal,
// atlas UV, then the material's inputs UV0, UV1, COLOR_0. Every pipeline over these buffers
// declares all of them (an attribute no shader declares is a validation warning).
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_atlas_uv;
layout(location = 3) in vec2 in_uv0;
layout(location = 4) in vec2 in_uv1;
layout(location = 5) in vec4 in_colour;
// Where a skinned twin's JOINTS_0 and WEIGHTS_0 go (object_vertex.glsl).
#define SKIN_LOCATION 6
