// Projection onto the receiving plane y = h along the light (DESIGN.md section 3). Mirrored on
// the CPU by technique::planar::project_onto_plane, which the tests compare against.
//   directional L (unit, L.y < 0): P' = P + L (P.y - h) / -L.y
//   point light C:                 P' = C + (P - C) (C.y - h) / (C.y - P.y)
// Points below the plane are clamped onto it (they cast nothing); a point level with or above a
// point light would project to infinity, so the denominator is kept positive.
vec3 project_onto_plane(vec3 p, vec4 light, float h) {
    vec3 q;
    if (light.w == 0.0) {
        vec3 l = normalize(light.xyz);
        float opposite = max(p.y - h, 0.0);
        q = p + l * (opposite / max(-l.y, 1e-3));
    } else {
        vec3 c = light.xyz;
        float py = max(p.y, h);
        float t = (c.y - h) / max(c.y - py, 1e-3 * (c.y - h));
        q = c + (vec3(p.x, py, p.z) - c) * t;
    }
    return vec3(q.x, h, q.z);
}
