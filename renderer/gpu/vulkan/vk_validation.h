/* vk_validation.h - the Khronos validation layer, on when $LUCENT_VALIDATION is 1: every warning and
 * error it reports goes to stderr as "lucent: vulkan validation: ...", which the tests look for. */
#ifndef LUCENT_VK_VALIDATION_H
#define LUCENT_VK_VALIDATION_H

#include "lucent.h"

#include <vulkan/vulkan.h>

/* Adds the layer and VK_EXT_debug_utils to an instance about to be created, when wanted. */
void vk_validation_request(VkInstanceCreateInfo *ici);
/* Installs the message callback on an instance created with vk_validation_request (no-op when
 * validation is off). */
lucent_status vk_validation_attach(VkInstance instance, VkDebugUtilsMessengerEXT *out, lucent_error *err);
void vk_validation_detach(VkInstance instance, VkDebugUtilsMessengerEXT messenger);

#endif
