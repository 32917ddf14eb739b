#version 450
// A shadow volume extruded here from its caster's tables, built once at load
// (src/mesh/shadow_mesh.rs, whose header says how): each index names one vertex of one
// candidate triangle, wound here by the sign of its multiplicity; the triangles the CPU
// builders would make for this light survive, vertex for vertex and in their winding, and the
// others collapse off screen. Facing and extrusion
// are computed exactly as the CPU computes them (`precise`: no fused multiply-add), so the
// volumes are the CPU's to the bit.
#include "frame_uniforms.glsl"
#include "volume_push.glsl"
#include "volume_far_point.glsl"

layout(std430, set = 1, binding = 0) readonly buffer ShadowMeshes {
    uint words[];
} meshes;

// How many counts this triangle adds (|m|; 1 per instance for the stencil).
layout(location = 0) flat out float weight;

// Invariant and written exactly as shadow_volume.vert and lit.vert write it, so that caps on
// the occluder's own triangles land on the same depths as the occluder.
invariant gl_Position;

uint word(uint at) {
    return meshes.words[object.mesh + at];
}

float word_float(uint at) {
    return uintBitsToFloat(word(at));
}

vec3 position(uint vertex) {
    uint at = word(3u) + 3u * vertex;
    return vec3(word_float(at), word_float(at + 1u), word_float(at + 2u));
}

// +1 where face `face` casts facing the light; where it faces away, -1 for a two-sided caster
// (it casts flipped), else 0. Lit when N . L < 0, L the direction the light travels to the face
// (mesh::shadow_volume::start_volume).
int casting(uint face) {
    uint at = word(0u) + 6u * face;
    vec3 n = vec3(word_float(at + 3u), word_float(at + 4u), word_float(at + 5u));
    precise vec3 travel = object.light.w == 0.0 ? object.light.xyz : position(word(at)) - object.light.xyz;
    precise float facing = n.x * travel.x + n.y * travel.y + n.z * travel.z;
    if (facing < 0.0) {
        return 1;
    }
    return word(7u) != 0u ? -1 : 0;
}

void main() {
    uint code = uint(gl_VertexIndex);
    uint role = code & 3u;
    uint slot = (code >> 4) & 3u;
    uint id = code >> 6;
    int m = 0;
    uint vertex;
    if ((code & 8u) != 0u) {
        // A wall: the edge's multiplicity over every face that has it; its ends in the order
        // the casting faces run it on balance (swapped where m < 0).
        uint at = word(1u) + 4u * id;
        uint first = word(2u) + word(at + 2u);
        uint count = word(at + 3u);
        for (uint i = 0u; i < count; i++) {
            uint entry = word(first + i);
            int c = casting(entry >> 1);
            m += (entry & 1u) != 0u ? c : -c;
        }
        vertex = word(at + (m < 0 ? 1u - slot : slot));
    } else {
        // A cap: its face, cast flipped (corners 1 and 2 swapped) where it faces away.
        uint at = word(0u) + 6u * id;
        m = casting(id);
        vertex = word(at + (m < 0 && slot != 0u ? 3u - slot : slot));
    }
    uint times = uint(abs(m));
    bool instanced = (object.flags & 1u) != 0u;
    if (m == 0 || (instanced && uint(gl_InstanceIndex) >= times)) {
        // Not drawn: every vertex of the triangle lands here, outside the clip volume.
        weight = 0.0;
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    weight = instanced ? 1.0 : float(times);
    vec4 point;
    if (role == 0u) {
        point = vec4(position(vertex), 1.0);
    } else if (role == 1u) {
        point = far_point(position(vertex));
    } else {
        point = far_point(vec3(word_float(4u), word_float(5u), word_float(6u)));
    }
    if (point.w == 0.0) {
        gl_Position = frame.view_proj * (object.model * vec4(point.xyz, 0.0));
    } else {
        vec4 world = object.model * vec4(point.xyz, 1.0);
        gl_Position = frame.view_proj * world;
    }
}
