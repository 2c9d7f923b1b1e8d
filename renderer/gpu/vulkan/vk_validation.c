/* vk_validation.c - opt-in Vulkan validation for development and the test suite; off in production,
 * where the layer costs time and may not be installed. */
#include "vk_validation.h"
#include "vk_check.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const layers[] = {"VK_LAYER_KHRONOS_validation"};
static const char *const extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};

static int wanted(void)
{
    const char *v = getenv("LUCENT_VALIDATION");
    return v && strcmp(v, "1") == 0;
}

void vk_validation_request(VkInstanceCreateInfo *ici)
{
    if (!wanted())
        return;
    ici->enabledLayerCount = 1;
    ici->ppEnabledLayerNames = layers;
    ici->enabledExtensionCount = 1;
    ici->ppEnabledExtensionNames = extensions;
}

static VKAPI_ATTR VkBool32 VKAPI_CALL report(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                             VkDebugUtilsMessageTypeFlagsEXT type,
                                             const VkDebugUtilsMessengerCallbackDataEXT *data, void *user)
{
    (void)type, (void)user;
    fprintf(stderr, "lucent: vulkan validation %s: %s\n",
            severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning", data->pMessage);
    return VK_FALSE;
}

lucent_status vk_validation_attach(VkInstance instance, VkDebugUtilsMessengerEXT *out, lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    *out = VK_NULL_HANDLE;
    if (!wanted())
        return LUCENT_OK;
    PFN_vkCreateDebugUtilsMessengerEXT create =
        (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT");
    if (!create)
        return lucent_fail(err, LUCENT_E_GPU, "", "LUCENT_VALIDATION=1 but VK_EXT_debug_utils is missing");
    VkDebugUtilsMessengerCreateInfoEXT ci = {.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
                                             .messageSeverity =
                                                 VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                                 VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
                                             .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                                                            VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                                            VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
                                             .pfnUserCallback = report};
    VK_TRY(create(instance, &ci, NULL, out), err);
    fprintf(stderr, "lucent: vulkan validation layer enabled\n");
fail:
    return st;
}

void vk_validation_detach(VkInstance instance, VkDebugUtilsMessengerEXT messenger)
{
    if (!messenger)
        return;
    PFN_vkDestroyDebugUtilsMessengerEXT destroy = (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
        instance, "vkDestroyDebugUtilsMessengerEXT");
    if (destroy)
        destroy(instance, messenger, NULL);
}
