#version 460
// What the user's camera sees (spec 004 passes B1 and §6.4), from the camera's item buffer
// (item_buffer.vert, camera mode): an element is seen when it lies in the camera's frustum,
// faces the eye, and is the nearest surface in its item-buffer pixel (within the bias).
// Importance: each element's directly received importance R' = scale x cos φ_cam cos φ_x / (π r²)
// (the camera a point), 0 when unseen, so elements that left the view lose theirs too; the
// change R' − R goes into the total and unshot importance (§4.2.6). Visibility: the surface
// of every seen element is in view (the thesis: one visible pixel makes a surface visible).
#include "gi/radiosity/radiosity.glsl"
#include "common/math.glsl"

#define VIEW_IMPORTANCE 1u
#define VIEW_VISIBILITY 2u

layout(local_size_x = LINEAR_WORKGROUP) in;

layout(binding = RAD_ELEMENTS, std430) readonly buffer Elements { Element elements[]; };
layout(binding = RAD_SURFACES, std430) readonly buffer Surfaces { SurfaceRecord surfaces[]; };
layout(binding = RAD_IMPORTANCE, std430) buffer Importance { float importance[]; };
layout(binding = RAD_IMPORTANCE_UNSHOT, std430) buffer ImportanceUnshot { float importance_unshot[]; };
layout(binding = RAD_IMPORTANCE_RECEIVED, std430) buffer ImportanceReceived { float received[]; };
layout(binding = RAD_VISIBLE, std430) writeonly buffer Visible { uint visible[]; };
layout(binding = RAD_ITEM_IDS, r32ui) readonly uniform uimage2DArray item_ids;
layout(binding = RAD_ITEM_DISTANCE, r32f) readonly uniform image2DArray item_distance;

layout(push_constant) uniform Push {
    mat4 camera;     // world to clip
    vec4 eye;        // xyz
    vec4 forward;    // xyz the camera's axis
    uint element_count;
    uint resolution;
    float bias;
    float scale;     // importance of a texel at unit distance on the axis, facing the eye
    uint flags;      // VIEW_*
} pc;

void main() {
    uint e = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * LINEAR_WORKGROUP + gl_GlobalInvocationID.x;
    if (e >= pc.element_count) return;
    Element element = elements[e];
    if (element.position_area.w <= 0.0) return;
    uint surface = floatBitsToUint(element.albedo_surface.w);
    vec3 x = element.position_area.xyz;
    vec4 clip = pc.camera * vec4(x, 1.0);
    vec3 v = x - pc.eye.xyz;
    float r2 = dot(v, v);
    float r = sqrt(r2);
    float cos_x = r > 0.0 ? -dot(surfaces[surface].normal.xyz, v / r) : 0.0;
    bool seen = clip.w > 0.0 && all(lessThanEqual(abs(clip.xy), vec2(clip.w)))
        && clip.z >= 0.0 && clip.z <= clip.w && cos_x > 0.0;
    if (seen) {
        vec2 ndc = clip.xy / clip.w;
        ivec2 pixel = clamp(ivec2(floor((ndc * 0.5 + 0.5) * float(pc.resolution))),
                            ivec2(0), ivec2(int(pc.resolution) - 1));
        uint id = imageLoad(item_ids, ivec3(pixel, 0)).x;
        float nearest = imageLoad(item_distance, ivec3(pixel, 0)).x;
        seen = id == surface + 1u || nearest >= r * (1.0 - pc.bias);
    }
    if ((pc.flags & VIEW_VISIBILITY) != 0u && seen) visible[surface] = 1u;
    if ((pc.flags & VIEW_IMPORTANCE) != 0u) {
        float cos_cam = max(dot(pc.forward.xyz, v / max(r, 1e-30)), 0.0);
        float now = seen ? pc.scale * cos_cam * cos_x / (PI * r2) : 0.0;
        float change = now - received[e];
        received[e] = now;
        importance[e] += change;
        importance_unshot[e] += change;
    }
}
