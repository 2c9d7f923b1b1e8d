/* vk_check.h - how a VkResult becomes a lucent_error: VK_TRY and the result's name. A leaf every
 * Vulkan file includes, so that the device and the validation layer need not include each other. */
#ifndef LUCENT_VK_CHECK_H
#define LUCENT_VK_CHECK_H

#include "lucent.h"

#include <vulkan/vulkan.h>

const char *vk_result_name(VkResult r);

/* VK_TRY is the one way a VkResult becomes a lucent_error. Needs `lucent_status st` and a
 * `fail:` label in the caller. */
#define VK_TRY(call, err)                                                                       \
    do {                                                                                        \
        VkResult vk_try_r_ = (call);                                                            \
        if (vk_try_r_ != VK_SUCCESS) {                                                          \
            st = lucent_fail((err), LUCENT_E_GPU, "", "%s failed: %s (%d; %s:%d)", #call,    \
                             vk_result_name(vk_try_r_), (int)vk_try_r_, __FILE__, __LINE__);    \
            goto fail;                                                                          \
        }                                                                                       \
    } while (0)

#endif
