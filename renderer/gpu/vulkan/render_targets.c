/* render_targets.c - creates the per-size GPU resources and wires them into descriptor sets, re-creating
 * only the group whose size changed. Everything here is owned by struct render_targets. */
#include "render_targets.h"

#include <string.h>

static lucent_status make_framebuffer(struct vk_context *ctx, VkRenderPass pass, const VkImageView *views,
                                      uint32_t count, uint32_t w, uint32_t h, VkFramebuffer *out,
                                      lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    VkFramebufferCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO, .renderPass = pass,
                                  .attachmentCount = count, .pAttachments = views, .width = w,
                                  .height = h, .layers = 1};
    VK_TRY(vkCreateFramebuffer(ctx->device, &ci, NULL, out), err);
fail:
    return st;
}

static lucent_status make_shadow_maps(struct vk_context *ctx, const struct pipelines *p,
                                      struct render_targets *t, lucent_error *err)
{
    lucent_status st = vk_image_create(ctx, SHADOW_MAP_SIZE, SHADOW_MAP_SIZE, LUCENT_MAX_LIGHTS, DEPTH_FORMAT,
                                       VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                                       &t->shadow_depth, err);
    for (uint32_t l = 0; st == LUCENT_OK && l < LUCENT_MAX_LIGHTS; l++) {
        st = vk_image_layer_view(ctx, &t->shadow_depth, l, &t->shadow_layer[l], err);
        if (st == LUCENT_OK)
            st = make_framebuffer(ctx, p->shadow_pass, &t->shadow_layer[l], 1, SHADOW_MAP_SIZE,
                                  SHADOW_MAP_SIZE, &t->shadow_fb[l], err);
    }
    return st;
}

static lucent_status make_projection(struct vk_context *ctx, const struct pipelines *p,
                                     struct render_targets *t, lucent_error *err)
{
    uint32_t s = t->projection_size, side = t->side_size;
    VkImageUsageFlags depth = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
    VkImageUsageFlags drawn = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                              VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    VkImageUsageFlags owned = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                              VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    VkImageUsageFlags copied = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    int shift = frame_owned_shift((int)s);
    lucent_status st;
    if ((st = vk_image_create_mipped(ctx, s, s, FRAME_MAX_VIEWS, frame_mip_levels(s), PROJECTION_FORMAT, drawn,
                                     &t->projection, err)) ||
        (st = vk_image_layer_view(ctx, &t->projection, 0, &t->front_layer, err)) ||
        (st = vk_image_create(ctx, s, s, FRAME_MAX_VIEWS, PROJECTION_FORMAT, drawn, &t->normals, err)) ||
        (st = vk_image_layer_view(ctx, &t->normals, 0, &t->front_normals, err)) ||
        (st = vk_image_create_mipped(ctx, s >> shift, s >> shift, FRAME_MAX_VIEWS, frame_mip_levels(s >> shift),
                                     PROJECTION_FORMAT, owned, &t->owned, err)) ||
        (st = vk_image_base_view(ctx, &t->owned, &t->owned_base, err)) ||
        (st = vk_image_create(ctx, s, s, 1, DEPTH_FORMAT, depth, &t->front_depth, err)) ||
        (st = vk_image_create(ctx, side, side, SIDE_VIEWS, PROJECTION_FORMAT, copied, &t->sides, err)) ||
        (st = vk_image_create(ctx, side, side, SIDE_VIEWS, PROJECTION_FORMAT, copied, &t->side_normals, err)) ||
        (st = vk_image_create(ctx, side, side, SIDE_VIEWS, DEPTH_FORMAT, depth, &t->sides_depth, err)) ||
        (st = vk_image_create(ctx, side, side, FRAME_LIGHT_VIEWS, PROJECTION_FORMAT, copied, &t->lights, err)) ||
        (st = vk_image_create(ctx, side, side, FRAME_LIGHT_VIEWS, PROJECTION_FORMAT, copied, &t->light_normals, err)) ||
        (st = vk_image_create(ctx, side, side, FRAME_LIGHT_VIEWS, DEPTH_FORMAT, depth, &t->lights_depth, err)))
        return st;
    VkImageView front[3] = {t->front_layer, t->front_normals, t->front_depth.view};
    VkImageView sides[3] = {t->sides.view, t->side_normals.view, t->sides_depth.view};
    if ((st = make_framebuffer(ctx, p->projection_pass[PROJECTION_FRONT], front, 3, s, s, &t->front_fb, err)))
        return st;
    VkImageView lights[3] = {t->lights.view, t->light_normals.view, t->lights_depth.view};
    if ((st = make_framebuffer(ctx, p->projection_pass[PROJECTION_SIDES], sides, 3, side, side, &t->sides_fb, err)))
        return st;
    return make_framebuffer(ctx, p->projection_pass[PROJECTION_LIGHTS], lights, 3, side, side, &t->lights_fb, err);
}

static lucent_status make_gbuffer(struct vk_context *ctx, const struct pipelines *p, struct render_targets *t,
                                  lucent_error *err)
{
    VkImageUsageFlags color = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    lucent_status st;
    if ((st = vk_image_create(ctx, t->width, t->height, 1, GBUFFER_FORMAT, color, &t->gbuffer_position, err)) ||
        (st = vk_image_create(ctx, t->width, t->height, 1, GBUFFER_FORMAT, color, &t->gbuffer_normal, err)) ||
        (st = vk_image_create(ctx, t->width, t->height, 1, DEPTH_FORMAT,
                              VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, &t->gbuffer_depth, err)))
        return st;
    VkImageView views[3] = {t->gbuffer_position.view, t->gbuffer_normal.view, t->gbuffer_depth.view};
    return make_framebuffer(ctx, p->gbuffer_pass, views, 3, t->width, t->height, &t->gbuffer_fb, err);
}

static VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize a)
{
    return a > 1 ? (v + a - 1) / a * a : v;
}

static lucent_status make_output(struct vk_context *ctx, struct render_targets *t, lucent_error *err)
{
    VkDeviceSize pixels = (VkDeviceSize)t->width * t->height;
    VkDeviceSize a = ctx->limits.minStorageBufferOffsetAlignment;
    t->color_offset = 0;
    t->normal_offset = align_up(pixels * 16, a);
    t->depth_offset = align_up(t->normal_offset + pixels * 16, a);
    lucent_status st = vk_buffer_create(ctx, t->depth_offset + pixels * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                        &t->output, err);
    if (st != LUCENT_OK)
        return st;
    uint32_t b = (uint32_t)frame_far_block((int)t->width, (int)t->height);
    VkDeviceSize blocks = (VkDeviceSize)frame_far_blocks(t->width, b) * frame_far_blocks(t->height, b);
    t->far_bytes = blocks * FRAME_FAR_SAMPLE_BYTES;
    /* Blocks of one pixel are not filtered (frame_record.c): the compose pass reads the far samples. */
    t->far_filtered_offset = b > 1 ? align_up(t->far_bytes, a) : 0;
    return vk_buffer_create(ctx, t->far_filtered_offset + t->far_bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, &t->far,
                            err);
}

static lucent_status make_descriptor_sets(struct vk_context *ctx, const struct pipelines *p,
                                          struct render_targets *t, lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 2},
                                    {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 6},
                                    {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 5},
                                    {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1}};
    VkDescriptorPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO, .maxSets = 2,
                                      .poolSizeCount = 4, .pPoolSizes = sizes};
    VK_TRY(vkCreateDescriptorPool(ctx->device, &pci, NULL, &t->pool), err);
    VkDescriptorSetLayout layouts[2] = {p->projection_set_layout, p->scatter_set_layout};
    VkDescriptorSet sets[2];
    VkDescriptorSetAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
                                      .descriptorPool = t->pool, .descriptorSetCount = 2, .pSetLayouts = layouts};
    VK_TRY(vkAllocateDescriptorSets(ctx->device, &ai, sets), err);
    t->projection_set = sets[0];
    t->scatter_set = sets[1];
fail:
    return st;
}

/* Points the descriptor sets at the current targets. The previous frame has finished (the renderer
 * waits for every frame) and its command buffer is recorded anew, so the sets may be updated. */
static void write_descriptor_sets(struct vk_context *ctx, const struct pipelines *p,
                                  const struct vk_buffer *uniforms, const struct render_targets *t)
{
    VkDescriptorBufferInfo ubo = {uniforms->buffer, 0, VK_WHOLE_SIZE};
    VkImageLayout ro = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    VkDescriptorImageInfo shadow = {p->shadow_compare, t->shadow_depth.view, ro};
    VkDescriptorImageInfo images[6] = {{p->filtered, t->projection.view, ro},
                                       {p->nearest, t->gbuffer_position.view, ro},
                                       {p->nearest, t->gbuffer_normal.view, ro},
                                       {p->filtered, t->owned.view, ro},
                                       {p->nearest, t->normals.view, ro},
                                       {VK_NULL_HANDLE, t->owned_base, VK_IMAGE_LAYOUT_GENERAL}};
    VkDeviceSize pixels = (VkDeviceSize)t->width * t->height;
    VkDescriptorBufferInfo outs[3] = {{t->output.buffer, t->color_offset, pixels * 16},
                                      {t->output.buffer, t->normal_offset, pixels * 16},
                                      {t->output.buffer, t->depth_offset, pixels * 4}};
    VkDescriptorBufferInfo far[2] = {{t->far.buffer, 0, t->far_bytes},
                                     {t->far.buffer, t->far_filtered_offset, t->far_bytes}};
#define WRITE(set, binding, type, img, buf) \
    {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, NULL, set, binding, 0, 1, type, img, buf, NULL}
    VkWriteDescriptorSet w[] = {
        WRITE(t->projection_set, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, NULL, &ubo),
        WRITE(t->projection_set, 1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &shadow, NULL),
        WRITE(t->scatter_set, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, NULL, &ubo),
        WRITE(t->scatter_set, 1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &images[0], NULL),
        WRITE(t->scatter_set, 2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &images[1], NULL),
        WRITE(t->scatter_set, 3, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &images[2], NULL),
        WRITE(t->scatter_set, 4, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, NULL, &outs[0]),
        WRITE(t->scatter_set, 5, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, NULL, &outs[1]),
        WRITE(t->scatter_set, 6, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, NULL, &outs[2]),
        WRITE(t->scatter_set, 7, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, NULL, &far[0]),
        WRITE(t->scatter_set, 8, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &images[3], NULL),
        WRITE(t->scatter_set, 9, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &images[4], NULL),
        WRITE(t->scatter_set, 10, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, &images[5], NULL),
        WRITE(t->scatter_set, 11, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, NULL, &far[1])};
#undef WRITE
    vkUpdateDescriptorSets(ctx->device, sizeof w / sizeof w[0], w, 0, NULL);
}

static VkImageMemoryBarrier to_shader_read(VkImage image, VkImageAspectFlags aspect, uint32_t levels,
                                           uint32_t first, uint32_t count)
{
    return (VkImageMemoryBarrier){.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                                  .oldLayout = VK_IMAGE_LAYOUT_UNDEFINED,
                                  .newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                  .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                  .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED, .image = image,
                                  .subresourceRange = {aspect, 0, levels, first, count},
                                  .dstAccessMask = VK_ACCESS_SHADER_READ_BIT};
}

/* Shadow layers, side images and mip levels that no frame has drawn yet are still bound for
 * sampling: give them a valid layout. The projection, normal and owned images are cleared once (no
 * flux, depth -1): frames write only the side views' corners of layers 1-4, and a bilinear read at a
 * corner's edge touches the texels beside it, so those must hold no flux rather than undefined
 * (possibly NaN) values; frames keep their layout transitions content-preserving for that reason.
 * Only new images are prepared: the others hold what the last frame left, in the layout it left. */
static lucent_status prepare_layouts(struct vk_context *ctx, struct render_targets *t, int new_shadow,
                                     int new_projection, lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    if (!new_shadow && !new_projection)
        return LUCENT_OK;
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    VK_TRY(vkBeginCommandBuffer(ctx->cmd, &bi), err);
    const struct vk_image *cleared[3] = {&t->projection, &t->normals, &t->owned};
    VkImageMemoryBarrier b[4];
    uint32_t barriers = 0;
    for (int i = 0; new_projection && i < 3; i++) {
        VkImageSubresourceRange all = {VK_IMAGE_ASPECT_COLOR_BIT, 0, cleared[i]->levels, 0, FRAME_MAX_VIEWS};
        VkImageMemoryBarrier to_clear = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                                         .oldLayout = VK_IMAGE_LAYOUT_UNDEFINED,
                                         .newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                         .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                         .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                         .image = cleared[i]->image, .subresourceRange = all,
                                         .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT};
        vkCmdPipelineBarrier(ctx->cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL,
                             0, NULL, 1, &to_clear);
        VkClearColorValue empty = {.float32 = {0.0f, 0.0f, 0.0f, -1.0f}};
        vkCmdClearColorImage(ctx->cmd, cleared[i]->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &empty, 1, &all);
        b[barriers] = to_shader_read(cleared[i]->image, VK_IMAGE_ASPECT_COLOR_BIT, cleared[i]->levels, 0,
                                     FRAME_MAX_VIEWS);
        b[barriers].oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
        b[barriers++].srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    }
    if (new_shadow)
        b[barriers++] = to_shader_read(t->shadow_depth.image, VK_IMAGE_ASPECT_DEPTH_BIT, 1, 0, LUCENT_MAX_LIGHTS);
    vkCmdPipelineBarrier(ctx->cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, NULL,
                         0, NULL, barriers, b);
    VK_TRY(vkEndCommandBuffer(ctx->cmd), err);
    st = vk_submit_and_wait(ctx, err);
fail:
    return st;
}

static void destroy_projection(struct vk_context *ctx, struct render_targets *t)
{
    VkDevice d = ctx->device;
    vkDestroyFramebuffer(d, t->lights_fb, NULL);
    vk_image_destroy(ctx, &t->lights_depth);
    vk_image_destroy(ctx, &t->light_normals);
    vk_image_destroy(ctx, &t->lights);
    vkDestroyFramebuffer(d, t->sides_fb, NULL);
    vk_image_destroy(ctx, &t->sides_depth);
    vk_image_destroy(ctx, &t->side_normals);
    vk_image_destroy(ctx, &t->sides);
    vkDestroyFramebuffer(d, t->front_fb, NULL);
    vk_image_destroy(ctx, &t->front_depth);
    vkDestroyImageView(d, t->owned_base, NULL);
    vk_image_destroy(ctx, &t->owned);
    vkDestroyImageView(d, t->front_normals, NULL);
    vk_image_destroy(ctx, &t->normals);
    vkDestroyImageView(d, t->front_layer, NULL);
    vk_image_destroy(ctx, &t->projection);
    t->lights_fb = t->sides_fb = t->front_fb = VK_NULL_HANDLE;
    t->owned_base = t->front_normals = t->front_layer = VK_NULL_HANDLE;
    t->projection_size = t->side_size = 0;
}

static void destroy_image_sized(struct vk_context *ctx, struct render_targets *t)
{
    vk_buffer_destroy(ctx, &t->far);
    vk_buffer_destroy(ctx, &t->output);
    vkDestroyFramebuffer(ctx->device, t->gbuffer_fb, NULL);
    t->gbuffer_fb = VK_NULL_HANDLE;
    vk_image_destroy(ctx, &t->gbuffer_depth);
    vk_image_destroy(ctx, &t->gbuffer_normal);
    vk_image_destroy(ctx, &t->gbuffer_position);
    t->width = t->height = 0;
}

lucent_status render_targets_fit(struct vk_context *ctx, const struct pipelines *p, const struct vk_buffer *uniforms,
                                 uint32_t width, uint32_t height, uint32_t projection_size, uint32_t side_size,
                                 struct render_targets *t, lucent_error *err)
{
    int new_shadow = t->shadow_depth.image == VK_NULL_HANDLE;
    int new_projection = t->projection_size != projection_size || t->side_size != side_size;
    int new_image = t->width != width || t->height != height;
    if (!new_shadow && !new_projection && !new_image)
        return LUCENT_OK;
    lucent_status st = LUCENT_OK;
    if (new_projection)
        destroy_projection(ctx, t);
    if (new_image)
        destroy_image_sized(ctx, t);
    t->projection_size = projection_size;
    t->side_size = side_size;
    t->width = width;
    t->height = height;
    if ((new_shadow && ((st = make_shadow_maps(ctx, p, t, err)) || (st = make_descriptor_sets(ctx, p, t, err)))) ||
        (new_projection && (st = make_projection(ctx, p, t, err))) ||
        (new_image && ((st = make_gbuffer(ctx, p, t, err)) || (st = make_output(ctx, t, err)))) ||
        (st = prepare_layouts(ctx, t, new_shadow, new_projection, err))) {
        render_targets_destroy(ctx, t);
        return st;
    }
    write_descriptor_sets(ctx, p, uniforms, t);
    return LUCENT_OK;
}

void render_targets_destroy(struct vk_context *ctx, struct render_targets *t)
{
    destroy_image_sized(ctx, t);
    destroy_projection(ctx, t);
    vkDestroyDescriptorPool(ctx->device, t->pool, NULL);
    for (int l = 0; l < LUCENT_MAX_LIGHTS; l++) {
        vkDestroyFramebuffer(ctx->device, t->shadow_fb[l], NULL);
        vkDestroyImageView(ctx->device, t->shadow_layer[l], NULL);
    }
    vk_image_destroy(ctx, &t->shadow_depth);
    memset(t, 0, sizeof *t);
}
