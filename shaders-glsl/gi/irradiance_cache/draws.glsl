#ifndef VKGI_IC_DRAWS_GLSL
#define VKGI_IC_DRAWS_GLSL
// The hemisphere passes' indirect draws: slot s draws the scene when the round has a record
// for it and nothing otherwise, so empty slots cost no vertex work.

struct DrawCommand {  // VkDrawIndirectCommand
    uint vertex_count;
    uint instance_count;
    uint first_vertex;
    uint first_instance;
};

layout(binding = IC_DRAWS, std430) writeonly buffer Draws { DrawCommand draws[]; };

// Draws for a round of `records` new records in `batch` slots.
void write_hemisphere_draws(uint records, uint batch, uint scene_vertices) {
    for (uint s = 0u; s < batch; ++s) {
        draws[s] = DrawCommand(s < records ? scene_vertices : 0u, 1u, 0u, 0u);
    }
}

#endif
