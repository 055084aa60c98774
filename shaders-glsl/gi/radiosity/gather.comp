#version 460
// Form-factor gather into every receiving element (spec 004 pass A4) from one shooting
// location: back-project the element into the location's item buffer; where it is visible,
// add the disc-approximation form factor F = a cos θs cos θx / (π r² + a) times the location's
// unshot radiosity (a light: its intensity toward the element times cos θx / r²) to the
// element's irradiance, and albedo times that to its unshot radiosity. Emission arriving is
// direct light, reflected radiosity arriving is indirect light (the display adds only the
// latter; the rasteriser draws the former). An importance shot adds the receiver's mean albedo
// times F times the location's unshot importance to its total and unshot importance (pass B2).
// pd: receivers out of the simulated view are skipped (the table keeps their share), and a
// delivery shoots each receiver's own table entry of the delivered column (§6.5).
#include "gi/radiosity/radiosity.glsl"
#include "common/math.glsl"
#include "common/lights.glsl"

layout(local_size_x = LINEAR_WORKGROUP) in;

// The elements (two texels each) and the surfaces (six) read as texels, bit for bit: lavapipe
// reads a storage buffer at an index that differs across lanes lane by lane, in a loop.
layout(binding = RAD_ELEMENTS) uniform usamplerBuffer elements;
layout(binding = RAD_SURFACES) uniform usamplerBuffer surfaces;
layout(binding = RAD_SHOT, std430) readonly buffer ShotBuffer { Shot shot; };
layout(binding = RAD_LOCATIONS, std430) readonly buffer Locations { Location locations[]; };
layout(binding = RAD_UNSHOT, std430) buffer Unshot { vec4 unshot[]; };
layout(binding = RAD_DIRECT, std430) buffer Direct { vec4 direct[]; };
layout(binding = RAD_INDIRECT, std430) buffer Indirect { vec4 indirect[]; };
layout(binding = RAD_IMPORTANCE, std430) buffer Importance { float importance[]; };
layout(binding = RAD_IMPORTANCE_UNSHOT, std430) buffer ImportanceUnshot { float importance_unshot[]; };
layout(binding = RAD_VISIBLE, std430) readonly buffer Visible { uint visible[]; };
layout(binding = RAD_TABLE, std430) readonly buffer Table { TableEntry table[]; };
layout(binding = RAD_DELIVERY, std430) readonly buffer DeliveryBuffer { Delivery delivery; };
layout(binding = RAD_ITEM_IDS, r32ui) readonly uniform uimage2DArray item_ids;
layout(binding = RAD_ITEM_DISTANCE, r32f) readonly uniform image2DArray item_distance;

layout(push_constant) uniform Push {
    uint slot;
    uint element_count;
    uint hemicube;
    uint resolution;
    float bias;      // relative: an element this much behind the nearest surface is still seen
    uint quantity;   // QUANTITY_*
    uint flags;      // GATHER_*
    uint surface_count;
} pc;

void main() {
    uint e = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * LINEAR_WORKGROUP + gl_GlobalInvocationID.x;
    // The location and the shot are read before the first return: lavapipe reads a buffer
    // once for all the lanes only at an index of constants and push constants outside every
    // branch (a return included), and lane by lane anywhere else.
    Location location = locations[pc.slot];
    uint shooter = shot.shooter;
    if (e >= pc.element_count) return;
    float kind = location.normal_kind.w;
    if (kind == LOCATION_NONE) return;
    Element element = Element(uintBitsToFloat(texelFetch(elements, 2 * int(e))),
                              uintBitsToFloat(texelFetch(elements, 2 * int(e) + 1)));
    float area = element.position_area.w;
    uint surface = floatBitsToUint(element.albedo_surface.w);
    bool deliver = (pc.flags & GATHER_DELIVER) != 0u;
    if (area <= 0.0 || (!deliver && kind == LOCATION_SURFACE && surface == shooter)) return;
    bool restricted = (pc.flags & (GATHER_RESTRICT | GATHER_DELIVER)) != 0u && kind == LOCATION_SURFACE;
    if (restricted && visible[surface] == 0u) return;
    if (deliver) {
        if (delivery.column == NO_COLUMN) return;
        TableEntry entry = table[delivery.column * pc.surface_count + surface];
        if (entry.emitted.rgb == vec3(0.0) && entry.reflected.rgb == vec3(0.0)) return;
        location.emitted.rgb = entry.emitted.rgb;
        location.reflected.rgb = entry.reflected.rgb;
    }
    vec3 s = location.position_area.xyz;
    vec3 n_s = location.normal_kind.xyz;
    vec3 v = element.position_area.xyz - s;
    float r2 = dot(v, v);
    if (r2 <= 0.0) return;
    float r = sqrt(r2);
    vec3 d = v / r;
    float cos_s = dot(n_s, d);
    float cos_x = -dot(uintBitsToFloat(texelFetch(surfaces, 6 * int(surface) + 3).xyz), d);
    if (cos_s <= 0.0 || cos_x <= 0.0) return;
    ivec3 texel = item_texel(d, n_s, pc.hemicube != 0u, pc.resolution);
    uint seen = imageLoad(item_ids, texel).x;
    float nearest = imageLoad(item_distance, texel).x;
    if (seen != surface + 1u && nearest < r * (1.0 - pc.bias) && pc.bias < 1.0) return;
    vec3 from_emission;
    vec3 from_reflection;
    if (pc.quantity == QUANTITY_IMPORTANCE) {
        float a = location.position_area.w;
        float f = a * cos_s * cos_x / (PI * r2 + a);
        float received = mean3(element.albedo_surface.rgb) * location.reflected.x * f;
        importance[e] += received;
        importance_unshot[e] += received;
        return;
    }
    if (kind == LOCATION_LIGHT) {
        float profile = spot_profile(dot(d, location.reflected.xyz), location.reflected.w,
                                     location.emitted.w);
        from_emission = location.emitted.rgb * (profile * cos_x / r2);
        from_reflection = vec3(0.0);
    } else {
        float a = location.position_area.w;
        float f = a * cos_s * cos_x / (PI * r2 + a);
        from_emission = location.emitted.rgb * f;
        from_reflection = location.reflected.rgb * f;
    }
    direct[e].rgb += from_emission;
    indirect[e].rgb += from_reflection;
    unshot[e].rgb += element.albedo_surface.rgb * (from_emission + from_reflection);
}
