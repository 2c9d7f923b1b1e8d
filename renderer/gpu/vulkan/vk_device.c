/* vk_device.c - creates headless instances and devices (no window system, no surface) and keeps them
 * in a small process-wide registry. Device choice prefers real GPUs, accepts lavapipe deliberately,
 * and is logged. */
#include "vk_device.h"
#include "gpu.h"

#include "vk_validation.h"

#include <stdio.h>
#include <string.h>

#define MAX_DEVICES 4

static struct vk_device registry[MAX_DEVICES];
static pthread_mutex_t registry_lock = PTHREAD_MUTEX_INITIALIZER;

static int device_rank(VkPhysicalDeviceType type)
{
    switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
    default: return 0;
    }
}

static int graphics_compute_family(VkPhysicalDevice dev)
{
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(dev, &count, NULL);
    VkQueueFamilyProperties props[16];
    if (count > 16)
        count = 16;
    vkGetPhysicalDeviceQueueFamilyProperties(dev, &count, props);
    VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    for (uint32_t i = 0; i < count; i++)
        if ((props[i].queueFlags & need) == need)
            return (int)i;
    return -1;
}

static int supports_multiview(VkPhysicalDevice dev)
{
    VkPhysicalDeviceMultiviewFeatures mv = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MULTIVIEW_FEATURES};
    VkPhysicalDeviceFeatures2 f = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, .pNext = &mv};
    vkGetPhysicalDeviceFeatures2(dev, &f);
    return mv.multiview == VK_TRUE;
}

static lucent_status pick_device(struct vk_device *dev, const char *wanted, lucent_error *err)
{
    VkPhysicalDevice devs[16];
    uint32_t count = 16;
    VkResult r = vkEnumeratePhysicalDevices(dev->instance, &count, devs);
    if ((r != VK_SUCCESS && r != VK_INCOMPLETE) || count == 0)
        return lucent_fail(err, LUCENT_E_GPU, "", "no Vulkan device found (%s); install "
                           "mesa-vulkan-drivers for the CPU renderer", vk_result_name(r));
    int best = -1, best_rank = -1;
    for (uint32_t i = 0; i < count; i++) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(devs[i], &p);
        if (p.apiVersion < VK_API_VERSION_1_1 || graphics_compute_family(devs[i]) < 0 ||
            !supports_multiview(devs[i]))
            continue;
        int rank = device_rank(p.deviceType);
        if (wanted && *wanted)
            rank = strstr(p.deviceName, wanted) ? 100 : -1;
        if (rank > best_rank)
            best = (int)i, best_rank = rank;
    }
    if (best < 0)
        return lucent_fail(err, LUCENT_E_GPU, "", wanted && *wanted
                           ? "no Vulkan 1.1 device with multiview matches \"%s\""
                           : "no Vulkan 1.1 device with multiview and a graphics+compute queue%s",
                           wanted && *wanted ? wanted : "");
    dev->physical = devs[best];
    dev->queue_family = (uint32_t)graphics_compute_family(dev->physical);
    return LUCENT_OK;
}

static void describe_device(struct vk_device *dev)
{
    VkPhysicalDeviceDriverProperties drv = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(dev->physical, &p);
    if (p.apiVersion >= VK_API_VERSION_1_2)
        p2.pNext = &drv;
    vkGetPhysicalDeviceProperties2(dev->physical, &p2);
    snprintf(dev->device_name, sizeof dev->device_name, "%s", p.deviceName);
    snprintf(dev->driver, sizeof dev->driver, "%s %s", p2.pNext ? drv.driverName : "unknown",
             p2.pNext ? drv.driverInfo : "");
    dev->api_version = p.apiVersion;
    dev->limits = p.limits;
    vkGetPhysicalDeviceMemoryProperties(dev->physical, &dev->memory);
}

/* Timestamps are optional: without them only CPU times are reported. */
static void probe_timestamps(struct vk_device *dev)
{
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(dev->physical, &count, NULL);
    VkQueueFamilyProperties props[16];
    if (count > 16)
        count = 16;
    vkGetPhysicalDeviceQueueFamilyProperties(dev->physical, &count, props);
    int valid = props[dev->queue_family].timestampValidBits > 0;
    dev->timestamp_ns = valid ? dev->limits.timestampPeriod : 0.0;
}

static void destroy_device(struct vk_device *d)
{
    if (d->device) {
        vkDeviceWaitIdle(d->device);
        vkDestroyDevice(d->device, NULL);
    }
    if (d->instance) {
        vk_validation_detach(d->instance, d->messenger);
        vkDestroyInstance(d->instance, NULL);
    }
    pthread_mutex_destroy(&d->queue_lock);
    memset(d, 0, sizeof *d);
}

static lucent_status create_device(struct vk_device *d, const char *request, lucent_error *err)
{
    lucent_status st = LUCENT_OK;
    memset(d, 0, sizeof *d);
    pthread_mutex_init(&d->queue_lock, NULL);
    snprintf(d->request, sizeof d->request, "%s", request);
    VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
                             .pApplicationName = "lucent", .apiVersion = VK_API_VERSION_1_1};
    VkInstanceCreateInfo ici = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO, .pApplicationInfo = &app};
    vk_validation_request(&ici);
    VK_TRY(vkCreateInstance(&ici, NULL, &d->instance), err);
    if ((st = vk_validation_attach(d->instance, &d->messenger, err)) != LUCENT_OK)
        goto fail;
    if ((st = pick_device(d, request, err)) != LUCENT_OK)
        goto fail;
    describe_device(d);
    probe_timestamps(d);
    float priority = 1.0f;
    VkDeviceQueueCreateInfo qci = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
                                   .queueFamilyIndex = d->queue_family, .queueCount = 1,
                                   .pQueuePriorities = &priority};
    VkPhysicalDeviceMultiviewFeatures mv = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MULTIVIEW_FEATURES,
                                            .multiview = VK_TRUE};
    VkDeviceCreateInfo dci = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, .pNext = &mv,
                              .queueCreateInfoCount = 1, .pQueueCreateInfos = &qci};
    VK_TRY(vkCreateDevice(d->physical, &dci, NULL, &d->device), err);
    vkGetDeviceQueue(d->device, d->queue_family, 0, &d->queue);
    return LUCENT_OK;
fail:
    destroy_device(d);
    return st;
}

lucent_status vk_device_acquire(const char *request, int verbose, struct vk_device **out, lucent_error *err)
{
    if (!request)
        request = "";
    /* The registry compares requests in full: one it could not hold would never match, and each
     * renderer would make a device of its own. */
    if (strlen(request) >= sizeof registry[0].request)
        return lucent_fail(err, LUCENT_E_LIMIT, "device", "a device name of at most %zu bytes (got %zu)",
                           sizeof registry[0].request - 1, strlen(request));
    pthread_mutex_lock(&registry_lock);
    struct vk_device *found = NULL, *free_slot = NULL;
    for (int i = 0; i < MAX_DEVICES; i++) {
        if (registry[i].device && !registry[i].lost && strcmp(registry[i].request, request) == 0)
            found = &registry[i];
        else if (!registry[i].device && !free_slot)
            free_slot = &registry[i];
    }
    lucent_status st = LUCENT_OK;
    if (!found && !free_slot)
        st = lucent_fail(err, LUCENT_E_LIMIT, "", "more than %d different Vulkan devices requested", MAX_DEVICES);
    else if (!found && (st = create_device(free_slot, request, err)) == LUCENT_OK)
        found = free_slot;
    if (found) {
        found->users++;
        *out = found;
        if (verbose)
            fprintf(stderr, "lucent: device \"%s\" (driver %s, Vulkan %u.%u.%u)\n", found->device_name,
                    found->driver, VK_API_VERSION_MAJOR(found->api_version), VK_API_VERSION_MINOR(found->api_version),
                    VK_API_VERSION_PATCH(found->api_version));
    }
    pthread_mutex_unlock(&registry_lock);
    return st;
}

void vk_device_release(struct vk_device *dev)
{
    pthread_mutex_lock(&registry_lock);
    if (--dev->users == 0 && dev->lost)
        destroy_device(dev);
    pthread_mutex_unlock(&registry_lock);
}

void vk_device_mark_lost(struct vk_device *dev)
{
    pthread_mutex_lock(&registry_lock);
    dev->lost = 1;
    pthread_mutex_unlock(&registry_lock);
}

void vk_gpu_release_idle(void)
{
    pthread_mutex_lock(&registry_lock);
    for (int i = 0; i < MAX_DEVICES; i++)
        if (registry[i].device && registry[i].users == 0)
            destroy_device(&registry[i]);
    pthread_mutex_unlock(&registry_lock);
}
