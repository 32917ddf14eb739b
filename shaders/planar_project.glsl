// Projection onto the receiving plane P = (n, d), n.x + d = 0 with unit n, along the light
// (docs/design/planar-shadows.md) through Blinn's shadow matrix M = (P.L) I - L P^T, L the light in
// homogeneous form (towards a directional light: (-dir, 0); a point light: (C, 1)). Mirrored on
// the CPU by technique::planar::Plane::project, which the tests compare against.
// Points behind the plane are first moved onto it (they cast nothing); a point level with or
// beyond a point light would project to infinity, so w is kept positive (the CPU refuses a
// light parallel to the plane, and the pass runs only where the light reaches it).
vec3 project_onto_plane(vec3 p, vec4 light, vec4 plane) {
    vec3 n = plane.xyz;
    p -= n * min(dot(n, p) + plane.w, 0.0);
    vec4 l = light.w == 0.0 ? vec4(-normalize(light.xyz), 0.0) : vec4(light.xyz, 1.0);
    float pl = dot(plane, l);
    mat4 shadow_matrix = pl * mat4(1.0) - outerProduct(l, plane);
    vec4 q = shadow_matrix * vec4(p, 1.0);
    vec3 projected = q.xyz / max(q.w, 1e-3 * pl);
    // Exactly on the plane (the division leaves rounding off it).
    return projected - n * (dot(n, projected) + plane.w);
}
