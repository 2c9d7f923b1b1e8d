/* pipelines.c - every fixed piece of GPU state: nothing here depends on image sizes or scenes,
 * so it is built once when the renderer starts and reused by every frame. */
#include "pipelines.h"

#include "gbuffer_frag.h"
#include "gbuffer_vert.h"
#include "ownership_comp.h"
#include "projection_frag.h"
#include "projection_vert.h"
#include "scatter_comp.h"
#include "shadow_vert.h"
#include "vk_device.h"

#include <string.h>

struct shader_code {
    const uint32_t *words;
    size_t size;
};
#define SHADER(name) ((struct shader_code){name, sizeof name})

/* Color attachments end up sampled by shaders, or copied when for_copy is set; the depth
 * attachment is kept only when sample_depth is set (shadow maps). */
static lucent_status make_render_pass(struct vk_context *ctx, uint32_t colors, VkFormat color_format,
                                      int sample_depth, uint32_t view_mask, int for_copy, VkRenderPass *out,
                                      lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    VkAttachmentDescription att[3];
    VkAttachmentReference color_ref[2];
    for (uint32_t i = 0; i < colors; i++) {
        att[i] = (VkAttachmentDescription){
            .format = color_format, .samples = VK_SAMPLE_COUNT_1_BIT,
            .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR, .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
            .stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE, .stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
            .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
            .finalLayout = for_copy ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
        color_ref[i] = (VkAttachmentReference){i, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    }
    att[colors] = (VkAttachmentDescription){
        .format = DEPTH_FORMAT, .samples = VK_SAMPLE_COUNT_1_BIT,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = sample_depth ? VK_ATTACHMENT_STORE_OP_STORE : VK_ATTACHMENT_STORE_OP_DONT_CARE,
        .stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE, .stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
        .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
        .finalLayout = sample_depth ? VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL
                                    : VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkAttachmentReference depth_ref = {colors, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub = {.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS,
                                .colorAttachmentCount = colors, .pColorAttachments = color_ref,
                                .pDepthStencilAttachment = &depth_ref};
    VkPipelineStageFlags readers = VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    VkPipelineStageFlags writers = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                   VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                                   VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    VkAccessFlags writes = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    if (for_copy)
        readers = VK_PIPELINE_STAGE_TRANSFER_BIT;
    VkAccessFlags reads = for_copy ? VK_ACCESS_TRANSFER_READ_BIT : VK_ACCESS_SHADER_READ_BIT;
    VkSubpassDependency deps[2] = {
        {VK_SUBPASS_EXTERNAL, 0, readers, writers, 0, writes, 0},
        {0, VK_SUBPASS_EXTERNAL, writers, readers, writes, reads, 0}};
    VkRenderPassMultiviewCreateInfo mv = {.sType = VK_STRUCTURE_TYPE_RENDER_PASS_MULTIVIEW_CREATE_INFO,
                                          .subpassCount = 1, .pViewMasks = &view_mask,
                                          .correlationMaskCount = 1, .pCorrelationMasks = &view_mask};
    VkRenderPassCreateInfo rci = {.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO,
                                  .pNext = view_mask ? &mv : NULL, .attachmentCount = colors + 1,
                                  .pAttachments = att, .subpassCount = 1, .pSubpasses = &sub,
                                  .dependencyCount = 2, .pDependencies = deps};
    VK_TRY(vkCreateRenderPass(ctx->device, &rci, NULL, out), err);
fail:
    return st;
}

static lucent_status make_module(struct vk_context *ctx, struct shader_code code, VkShaderModule *out,
                                 lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    VkShaderModuleCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
                                   .codeSize = code.size, .pCode = code.words};
    VK_TRY(vkCreateShaderModule(ctx->device, &ci, NULL, out), err);
fail:
    return st;
}

struct raster_desc {
    VkRenderPass pass;
    VkPipelineLayout layout;
    struct shader_code vert, frag;   /* frag.words NULL: depth only */
    const VkSpecializationInfo *frag_constants;
    uint32_t colors;
    int with_normals;                /* second vertex binding */
    int cull;                        /* cull back faces: only for closed, outward-wound meshes */
};

static lucent_status make_raster_pipeline(struct vk_context *ctx, const struct raster_desc *d,
                                          VkPipeline *out, lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    VkShaderModule vert = VK_NULL_HANDLE, frag = VK_NULL_HANDLE;
    if ((st = make_module(ctx, d->vert, &vert, err)) != LUCENT_OK)
        goto fail;
    if (d->frag.words && (st = make_module(ctx, d->frag, &frag, err)) != LUCENT_OK)
        goto fail;
    VkPipelineShaderStageCreateInfo stages[2] = {
        {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, .stage = VK_SHADER_STAGE_VERTEX_BIT,
         .module = vert, .pName = "main"},
        {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, .stage = VK_SHADER_STAGE_FRAGMENT_BIT,
         .module = frag, .pName = "main", .pSpecializationInfo = d->frag_constants}};
    VkVertexInputBindingDescription bindings[2] = {{0, 12, VK_VERTEX_INPUT_RATE_VERTEX},
                                                   {1, 16, VK_VERTEX_INPUT_RATE_VERTEX}};
    VkVertexInputAttributeDescription attrs[2] = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
                                                  {1, 1, VK_FORMAT_R32G32B32A32_SFLOAT, 0}};
    uint32_t streams = d->with_normals ? 2 : 1;
    VkPipelineVertexInputStateCreateInfo vi = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO,
        .vertexBindingDescriptionCount = streams, .pVertexBindingDescriptions = bindings,
        .vertexAttributeDescriptionCount = streams, .pVertexAttributeDescriptions = attrs};
    VkPipelineInputAssemblyStateCreateInfo ia = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO,
        .topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST};
    VkPipelineViewportStateCreateInfo vp = {.sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO,
                                            .viewportCount = 1, .scissorCount = 1};
    /* Without culling, open meshes and flipped windings still draw and the shaders face-forward
     * normals with gl_FrontFacing. Vulkan's area sign already accounts for its y-down framebuffer,
     * so counter-clockwise-from-outside meshes stay front-facing with our y-down clip space. */
    VkPipelineRasterizationStateCreateInfo rs = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO,
        .polygonMode = VK_POLYGON_MODE_FILL, .cullMode = d->cull ? VK_CULL_MODE_BACK_BIT : VK_CULL_MODE_NONE,
        .frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE, .lineWidth = 1.0f};
    VkPipelineMultisampleStateCreateInfo ms = {.sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO,
                                               .rasterizationSamples = VK_SAMPLE_COUNT_1_BIT};
    VkPipelineDepthStencilStateCreateInfo ds = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO, .depthTestEnable = VK_TRUE,
        .depthWriteEnable = VK_TRUE, .depthCompareOp = VK_COMPARE_OP_LESS};
    VkPipelineColorBlendAttachmentState blend[2] = {{.colorWriteMask = 0xf}, {.colorWriteMask = 0xf}};
    VkPipelineColorBlendStateCreateInfo cb = {.sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO,
                                              .attachmentCount = d->colors, .pAttachments = blend};
    VkDynamicState dyn[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dy = {.sType = VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO,
                                           .dynamicStateCount = 2, .pDynamicStates = dyn};
    VkGraphicsPipelineCreateInfo gci = {
        .sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO, .stageCount = frag ? 2 : 1,
        .pStages = stages, .pVertexInputState = &vi, .pInputAssemblyState = &ia, .pViewportState = &vp,
        .pRasterizationState = &rs, .pMultisampleState = &ms, .pDepthStencilState = &ds,
        .pColorBlendState = &cb, .pDynamicState = &dy, .layout = d->layout, .renderPass = d->pass};
    VK_TRY(vkCreateGraphicsPipelines(ctx->device, VK_NULL_HANDLE, 1, &gci, NULL, out), err);
fail:
    if (vert)
        vkDestroyShaderModule(ctx->device, vert, NULL);
    if (frag)
        vkDestroyShaderModule(ctx->device, frag, NULL);
    return st;
}

static lucent_status make_set_layout(struct vk_context *ctx, const VkDescriptorType *types, uint32_t count,
                                     VkShaderStageFlags stages, VkDescriptorSetLayout *out, lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    VkDescriptorSetLayoutBinding b[SCATTER_BINDINGS];
    for (uint32_t i = 0; i < count; i++)
        b[i] = (VkDescriptorSetLayoutBinding){i, types[i], 1, stages, NULL};
    VkDescriptorSetLayoutCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
                                          .bindingCount = count, .pBindings = b};
    VK_TRY(vkCreateDescriptorSetLayout(ctx->device, &ci, NULL, out), err);
fail:
    return st;
}

static lucent_status make_layout(struct vk_context *ctx, VkDescriptorSetLayout set, uint32_t push_size,
                                 VkShaderStageFlags push_stages, VkPipelineLayout *out, lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    VkPushConstantRange range = {push_stages, 0, push_size};
    VkPipelineLayoutCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
                                     .setLayoutCount = set ? 1 : 0, .pSetLayouts = &set,
                                     .pushConstantRangeCount = push_size ? 1 : 0, .pPushConstantRanges = &range};
    VK_TRY(vkCreatePipelineLayout(ctx->device, &ci, NULL, out), err);
fail:
    return st;
}

/* A compute pipeline over the scatter pass's descriptor set (scatter.comp, ownership.comp). */
static lucent_status make_compute_pipeline(struct vk_context *ctx, struct pipelines *p, struct shader_code code,
                                           const VkSpecializationInfo *spec, VkPipeline *out, lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    VkShaderModule module = VK_NULL_HANDLE;
    if ((st = make_module(ctx, code, &module, err)) != LUCENT_OK)
        return st;
    VkComputePipelineCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
        .stage = {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                  .stage = VK_SHADER_STAGE_COMPUTE_BIT, .module = module, .pName = "main",
                  .pSpecializationInfo = spec},
        .layout = p->scatter_layout};
    VK_TRY(vkCreateComputePipelines(ctx->device, VK_NULL_HANDLE, 1, &ci, NULL, out), err);
fail:
    vkDestroyShaderModule(ctx->device, module, NULL);
    return st;
}

static lucent_status make_layouts(struct vk_context *ctx, struct pipelines *p, lucent_error *err)
{
    lucent_status st;
    const VkDescriptorType projection_types[] = {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                                                 VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER};
    const VkDescriptorType scatter_types[] = {
        VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
        VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
        VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
        VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
        VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
    VkShaderStageFlags raster = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    if ((st = make_set_layout(ctx, projection_types, 2, raster, &p->projection_set_layout, err)) ||
        (st = make_set_layout(ctx, scatter_types, SCATTER_BINDINGS, VK_SHADER_STAGE_COMPUTE_BIT,
                                &p->scatter_set_layout, err)) ||
        (st = make_layout(ctx, VK_NULL_HANDLE, 64, VK_SHADER_STAGE_VERTEX_BIT, &p->shadow_layout, err)) ||
        (st = make_layout(ctx, p->projection_set_layout, sizeof(int32_t), raster, &p->projection_layout, err)) ||
        (st = make_layout(ctx, VK_NULL_HANDLE, sizeof(struct gbuffer_push), raster, &p->gbuffer_layout, err)) ||
        (st = make_layout(ctx, p->scatter_set_layout, 8, VK_SHADER_STAGE_COMPUTE_BIT, &p->scatter_layout, err)))
        return st;
    return LUCENT_OK;
}

/* The projection images' mip chain is made by linear blits and read with linear filtering. */
static lucent_status check_projection_format(struct vk_context *ctx, lucent_error *err)
{
    VkFormatProperties props;
    vkGetPhysicalDeviceFormatProperties(ctx->shared->physical, PROJECTION_FORMAT, &props);
    VkFormatFeatureFlags need = VK_FORMAT_FEATURE_BLIT_SRC_BIT | VK_FORMAT_FEATURE_BLIT_DST_BIT |
                                VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT;
    if ((props.optimalTilingFeatures & need) != need)
        return lucent_fail(err, LUCENT_E_GPU, "", "device %s cannot blit and linearly filter "
                           "VK_FORMAT_R32G32B32A32_SFLOAT (the projection images' mip chain)", ctx->device_name);
    return LUCENT_OK;
}

static lucent_status make_sampler(struct vk_context *ctx, int compare, VkFilter filter, VkSampler *out,
                                  lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    VkSamplerCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO,
                              .magFilter = filter, .minFilter = filter,
                              .mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST, .maxLod = VK_LOD_CLAMP_NONE,
                              .addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
                              .addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
                              .addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
                              .compareEnable = compare ? VK_TRUE : VK_FALSE,
                              .compareOp = VK_COMPARE_OP_LESS_OR_EQUAL};
    VK_TRY(vkCreateSampler(ctx->device, &ci, NULL, out), err);
fail:
    return st;
}

lucent_status pipelines_create(struct vk_context *ctx, struct pipelines *p, lucent_error *err)
{
    lucent_status st;
    memset(p, 0, sizeof *p);
    if ((st = check_projection_format(ctx, err)) ||
        (st = make_render_pass(ctx, 0, VK_FORMAT_UNDEFINED, 1, 0, 0, &p->shadow_pass, err)) ||
        (st = make_render_pass(ctx, 2, PROJECTION_FORMAT, 0, 0, 0, &p->projection_pass[PROJECTION_FRONT], err)) ||
        (st = make_render_pass(ctx, 2, PROJECTION_FORMAT, 0, (1u << SIDE_VIEWS) - 1, 1,
                               &p->projection_pass[PROJECTION_SIDES], err)) ||
        (st = make_render_pass(ctx, 2, PROJECTION_FORMAT, 0, (1u << FRAME_LIGHT_VIEWS) - 1, 1,
                               &p->projection_pass[PROJECTION_LIGHTS], err)) ||
        (st = make_render_pass(ctx, 2, GBUFFER_FORMAT, 0, 0, 0, &p->gbuffer_pass, err)) ||
        (st = make_layouts(ctx, p, err)) || (st = make_sampler(ctx, 0, VK_FILTER_NEAREST, &p->nearest, err)) ||
        (st = make_sampler(ctx, 0, VK_FILTER_LINEAR, &p->filtered, err)) ||
        (st = make_sampler(ctx, 1, VK_FILTER_LINEAR, &p->shadow_compare, err)) ||
        (st = make_compute_pipeline(ctx, p, SHADER(ownership_comp), NULL, &p->ownership, err)))
        goto fail;

    for (int cull = 0; cull < 2; cull++) {
        struct raster_desc shadow = {p->shadow_pass, p->shadow_layout, SHADER(shadow_vert), {NULL, 0}, NULL, 0, 0,
                                     cull};
        struct raster_desc gbuffer = {p->gbuffer_pass, p->gbuffer_layout, SHADER(gbuffer_vert),
                                      SHADER(gbuffer_frag), NULL, 2, 1, cull};
        if ((st = make_raster_pipeline(ctx, &shadow, &p->shadow[cull], err)) ||
            (st = make_raster_pipeline(ctx, &gbuffer, &p->gbuffer[cull], err)))
            goto fail;
    }
    return LUCENT_OK;
fail:
    pipelines_destroy(ctx, p);
    return st;
}

static void destroy_pipeline(void *device, uint64_t pipeline)
{
    vkDestroyPipeline((VkDevice)device, (VkPipeline)pipeline, NULL);
}

/* The kept pipeline for key in *out, or VK_NULL_HANDLE in *out and in *slot where a new one goes. */
static lucent_status find_or_make_room(struct vk_context *ctx, struct pipeline_lru *lru, uint64_t key, uint64_t frame,
                                       const char *kind, VkPipeline *out, int *slot, lucent_error *err)
{
    uint64_t found, evicted;
    lucent_status st = pipeline_lru_get(lru, key, frame, kind, &found, slot, &evicted, err);
    if (evicted)
        destroy_pipeline(ctx->device, evicted);
    *out = (VkPipeline)found;
    return st;
}

lucent_status pipelines_projection(struct vk_context *ctx, struct pipelines *p, int which, int lights,
                                   uint32_t shadow_mask, int cull, VkPipeline *out, lucent_error *err)
{
    uint64_t key;
    int slot;
    lucent_status st = projection_variant_key(which, lights, shadow_mask, cull, &key, err);
    if (st == LUCENT_OK)
        st = find_or_make_room(ctx, &p->projection, key, p->frame, "projection", out, &slot, err);
    if (st != LUCENT_OK || *out)
        return st;
    int32_t values[PROJECTION_CONSTANTS];
    projection_variant_constants(lights, shadow_mask, values);
    VkSpecializationMapEntry entries[PROJECTION_CONSTANTS] = {{0, 0, 4}, {1, 4, 4}};
    VkSpecializationInfo spec = {PROJECTION_CONSTANTS, entries, sizeof values, values};
    struct raster_desc proj = {p->projection_pass[which], p->projection_layout, SHADER(projection_vert),
                               SHADER(projection_frag), &spec, 2, 1, cull};
    st = make_raster_pipeline(ctx, &proj, out, err);
    if (st == LUCENT_OK)
        pipeline_lru_put(&p->projection, slot, key, (uint64_t)*out, p->frame);
    return st;
}

lucent_status pipelines_scatter(struct vk_context *ctx, struct pipelines *p, const struct scatter_variant *v,
                                VkPipeline *out, lucent_error *err)
{
    uint64_t key;
    int slot;
    lucent_status st = scatter_variant_key(v, &key, err);
    if (st == LUCENT_OK)
        st = find_or_make_room(ctx, &p->scatter, key, p->frame, "scatter", out, &slot, err);
    if (st != LUCENT_OK || *out)
        return st;
    int32_t values[SCATTER_CONSTANTS];
    scatter_variant_constants(v, values);
    VkSpecializationMapEntry entries[SCATTER_CONSTANTS];
    for (uint32_t i = 0; i < SCATTER_CONSTANTS; i++)
        entries[i] = (VkSpecializationMapEntry){i, 4 * i, 4};
    VkSpecializationInfo spec = {SCATTER_CONSTANTS, entries, sizeof values, values};
    st = make_compute_pipeline(ctx, p, SHADER(scatter_comp), &spec, out, err);
    if (st == LUCENT_OK)
        pipeline_lru_put(&p->scatter, slot, key, (uint64_t)*out, p->frame);
    return st;
}

void pipelines_begin_frame(struct pipelines *p)
{
    p->frame++;
}

void pipelines_destroy(struct vk_context *ctx, struct pipelines *p)
{
    VkDevice d = ctx->device;
    for (int cull = 0; cull < 2; cull++) {
        vkDestroyPipeline(d, p->shadow[cull], NULL);
        vkDestroyPipeline(d, p->gbuffer[cull], NULL);
    }
    pipeline_lru_clear(&p->projection, destroy_pipeline, d);
    pipeline_lru_clear(&p->scatter, destroy_pipeline, d);
    vkDestroyPipeline(d, p->ownership, NULL);
    VkPipelineLayout layouts[] = {p->shadow_layout, p->projection_layout, p->gbuffer_layout, p->scatter_layout};
    for (size_t i = 0; i < sizeof layouts / sizeof layouts[0]; i++)
        vkDestroyPipelineLayout(d, layouts[i], NULL);
    vkDestroyDescriptorSetLayout(d, p->projection_set_layout, NULL);
    vkDestroyDescriptorSetLayout(d, p->scatter_set_layout, NULL);
    VkRenderPass passes[] = {p->shadow_pass, p->projection_pass[0], p->projection_pass[1], p->projection_pass[2],
                             p->gbuffer_pass};
    for (size_t i = 0; i < sizeof passes / sizeof passes[0]; i++)
        vkDestroyRenderPass(d, passes[i], NULL);
    vkDestroySampler(d, p->nearest, NULL);
    vkDestroySampler(d, p->filtered, NULL);
    vkDestroySampler(d, p->shadow_compare, NULL);
    memset(p, 0, sizeof *p);
}
