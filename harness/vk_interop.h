// Vulkan side of the external-memory path, shared by samples/render/pbf_render_vk.cpp and the
// [gpu] interop tests (header-only C++17): a Vulkan 1.2 device on the same GPU as the world
// (matched by UUID), a device-local buffer exported as an opaque fd, binary and timeline
// semaphores exported as opaque fds, and a round trip that checks what the world copied into
// the buffer against pbf_world_copy_positions.
//
// The round trip, per frame f:
//   pbf_world_step
//   the world's stream waits for Vulkan's "done" semaphore of frame f-1 (timeline on odd
//   frames, binary on even ones), copies positions + draw count into the Vulkan buffer, and
//   signals "ready" (binary on odd frames, timeline = f on even ones)
//   Vulkan waits for "ready", copies the buffer into host-visible memory, signals "done"
//   the host waits for Vulkan's fence and compares with pbf_world_copy_positions
// so every semaphore kind is used in both directions. The copy is either explicit
// (pbf_world_copy_to_external_buffer with the sync) or automatic after each step
// (PBF_COPY_ON_STEP with pbf_world_set_external_sync before the step).
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "pbf_c_api.h"

namespace pbf_vk {

// A zeroed Vulkan struct with its sType set.
template <class T>
T make(VkStructureType type) {
    T v{};
    v.sType = type;
    return v;
}

struct Context {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    uint32_t queue_family = 0;
    VkQueue queue = VK_NULL_HANDLE;
    VkCommandPool pool = VK_NULL_HANDLE;
    VkPhysicalDeviceMemoryProperties memory{};
    PFN_vkGetMemoryFdKHR get_memory_fd = nullptr;
    PFN_vkGetSemaphoreFdKHR get_semaphore_fd = nullptr;
    std::string device_name;
    uint32_t api_version = 0;
};

inline std::string vk_text(const char* what, VkResult r) {
    return std::string(what) + " failed (VkResult " + std::to_string(int(r)) + ")";
}

inline bool has_extension(const std::vector<VkExtensionProperties>& list, const char* name) {
    for (const auto& e : list)
        if (std::strcmp(e.extensionName, name) == 0) return true;
    return false;
}

// Instance and device on the physical device whose deviceUUID is uuid (the world's GPU).
inline bool init(Context& c, const uint8_t uuid[16], std::string* err) {
    VkApplicationInfo app = make<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
    app.pApplicationName = "libpbf interop";
    app.apiVersion = VK_API_VERSION_1_2;
    VkInstanceCreateInfo ici = make<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
    ici.pApplicationInfo = &app;
    VkResult r = vkCreateInstance(&ici, nullptr, &c.instance);
    if (r != VK_SUCCESS)
        return *err = vk_text("vkCreateInstance (is the NVIDIA Vulkan ICD visible? VK_DRIVER_FILES)", r), false;
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(c.instance, &n, nullptr);
    std::vector<VkPhysicalDevice> devices(n);
    vkEnumeratePhysicalDevices(c.instance, &n, devices.data());
    for (VkPhysicalDevice d : devices) {
        VkPhysicalDeviceIDProperties id =
            make<VkPhysicalDeviceIDProperties>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ID_PROPERTIES);
        VkPhysicalDeviceProperties2 p2 =
            make<VkPhysicalDeviceProperties2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2);
        p2.pNext = &id;
        vkGetPhysicalDeviceProperties2(d, &p2);
        if (std::memcmp(id.deviceUUID, uuid, VK_UUID_SIZE) == 0) {
            c.physical = d;
            c.device_name = p2.properties.deviceName;
            c.api_version = p2.properties.apiVersion;
            break;
        }
    }
    if (!c.physical)
        return *err = "no Vulkan physical device has the CUDA device's UUID (" + std::to_string(n) + " devices)", false;
    uint32_t ne = 0;
    vkEnumerateDeviceExtensionProperties(c.physical, nullptr, &ne, nullptr);
    std::vector<VkExtensionProperties> exts(ne);
    vkEnumerateDeviceExtensionProperties(c.physical, nullptr, &ne, exts.data());
    const char* needed[] = {VK_KHR_EXTERNAL_MEMORY_FD_EXTENSION_NAME, VK_KHR_EXTERNAL_SEMAPHORE_FD_EXTENSION_NAME};
    for (const char* e : needed)
        if (!has_extension(exts, e)) return *err = std::string("the device lacks ") + e, false;
    uint32_t nq = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(c.physical, &nq, nullptr);
    std::vector<VkQueueFamilyProperties> families(nq);
    vkGetPhysicalDeviceQueueFamilyProperties(c.physical, &nq, families.data());
    c.queue_family = UINT32_MAX;
    for (uint32_t i = 0; i < nq; ++i)
        if (families[i].queueFlags & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT | VK_QUEUE_TRANSFER_BIT)) {
            c.queue_family = i;
            break;
        }
    if (c.queue_family == UINT32_MAX) return *err = "no queue family can transfer", false;
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo qci = make<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
    qci.queueFamilyIndex = c.queue_family;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;
    VkPhysicalDeviceVulkan12Features f12 =
        make<VkPhysicalDeviceVulkan12Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES);
    f12.timelineSemaphore = VK_TRUE;
    VkDeviceCreateInfo dci = make<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
    dci.pNext = &f12;
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    dci.enabledExtensionCount = 2;
    dci.ppEnabledExtensionNames = needed;
    r = vkCreateDevice(c.physical, &dci, nullptr, &c.device);
    if (r != VK_SUCCESS)
        return *err = vk_text("vkCreateDevice (timeline semaphores, external fd extensions)", r), false;
    vkGetDeviceQueue(c.device, c.queue_family, 0, &c.queue);
    VkCommandPoolCreateInfo pci = make<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = c.queue_family;
    r = vkCreateCommandPool(c.device, &pci, nullptr, &c.pool);
    if (r != VK_SUCCESS) return *err = vk_text("vkCreateCommandPool", r), false;
    vkGetPhysicalDeviceMemoryProperties(c.physical, &c.memory);
    c.get_memory_fd = reinterpret_cast<PFN_vkGetMemoryFdKHR>(vkGetDeviceProcAddr(c.device, "vkGetMemoryFdKHR"));
    c.get_semaphore_fd =
        reinterpret_cast<PFN_vkGetSemaphoreFdKHR>(vkGetDeviceProcAddr(c.device, "vkGetSemaphoreFdKHR"));
    if (!c.get_memory_fd || !c.get_semaphore_fd) return *err = "vkGetMemoryFdKHR / vkGetSemaphoreFdKHR missing", false;
    return true;
}

inline void shutdown(Context& c) {
    if (c.device) {
        vkDeviceWaitIdle(c.device);
        if (c.pool) vkDestroyCommandPool(c.device, c.pool, nullptr);
        vkDestroyDevice(c.device, nullptr);
    }
    if (c.instance) vkDestroyInstance(c.instance, nullptr);
    c = Context{};
}

inline uint32_t memory_type(const Context& c, uint32_t bits, VkMemoryPropertyFlags want) {
    for (uint32_t i = 0; i < c.memory.memoryTypeCount; ++i)
        if ((bits & (1u << i)) && (c.memory.memoryTypes[i].propertyFlags & want) == want) return i;
    return UINT32_MAX;
}

struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize size = 0;   // the allocation's size (what CUDA imports)
    void* mapped = nullptr;  // host-visible buffers
};

inline void destroy(const Context& c, Buffer& b) {
    if (b.mapped) vkUnmapMemory(c.device, b.memory);
    if (b.buffer) vkDestroyBuffer(c.device, b.buffer, nullptr);
    if (b.memory) vkFreeMemory(c.device, b.memory, nullptr);
    b = Buffer{};
}

// exported: device-local, a dedicated allocation exportable as an opaque fd (*fd set);
// otherwise host-visible and mapped.
inline bool create_buffer(const Context& c, VkDeviceSize bytes, bool exported, Buffer* b, int* fd, std::string* err) {
    VkExternalMemoryBufferCreateInfo ext =
        make<VkExternalMemoryBufferCreateInfo>(VK_STRUCTURE_TYPE_EXTERNAL_MEMORY_BUFFER_CREATE_INFO);
    ext.handleTypes = VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT;
    VkBufferCreateInfo bci = make<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
    bci.pNext = exported ? &ext : nullptr;
    bci.size = bytes;
    bci.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                (exported ? VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT
                          : 0);
    bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VkResult r = vkCreateBuffer(c.device, &bci, nullptr, &b->buffer);
    if (r != VK_SUCCESS) return *err = vk_text("vkCreateBuffer", r), false;
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(c.device, b->buffer, &req);
    const VkMemoryPropertyFlags want = exported
                                           ? VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT
                                           : VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    VkMemoryDedicatedAllocateInfo dedicated =
        make<VkMemoryDedicatedAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_DEDICATED_ALLOCATE_INFO);
    dedicated.buffer = b->buffer;
    VkExportMemoryAllocateInfo export_info =
        make<VkExportMemoryAllocateInfo>(VK_STRUCTURE_TYPE_EXPORT_MEMORY_ALLOCATE_INFO);
    export_info.pNext = &dedicated;
    export_info.handleTypes = VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT;
    VkMemoryAllocateInfo mai = make<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
    mai.pNext = exported ? &export_info : nullptr;
    mai.allocationSize = req.size;
    mai.memoryTypeIndex = memory_type(c, req.memoryTypeBits, want);
    if (mai.memoryTypeIndex == UINT32_MAX) return *err = "no suitable Vulkan memory type", false;
    r = vkAllocateMemory(c.device, &mai, nullptr, &b->memory);
    if (r != VK_SUCCESS) return *err = vk_text("vkAllocateMemory", r), false;
    b->size = req.size;
    r = vkBindBufferMemory(c.device, b->buffer, b->memory, 0);
    if (r != VK_SUCCESS) return *err = vk_text("vkBindBufferMemory", r), false;
    if (exported) {
        VkMemoryGetFdInfoKHR gi = make<VkMemoryGetFdInfoKHR>(VK_STRUCTURE_TYPE_MEMORY_GET_FD_INFO_KHR);
        gi.memory = b->memory;
        gi.handleType = VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT;
        r = c.get_memory_fd(c.device, &gi, fd);
        if (r != VK_SUCCESS) return *err = vk_text("vkGetMemoryFdKHR", r), false;
    } else {
        r = vkMapMemory(c.device, b->memory, 0, VK_WHOLE_SIZE, 0, &b->mapped);
        if (r != VK_SUCCESS) return *err = vk_text("vkMapMemory", r), false;
    }
    return true;
}

// A semaphore exportable as an opaque fd (*fd set), binary or timeline (initial value 0).
inline bool create_semaphore(const Context& c, bool timeline, VkSemaphore* s, int* fd, std::string* err) {
    VkSemaphoreTypeCreateInfo type = make<VkSemaphoreTypeCreateInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO);
    type.semaphoreType = timeline ? VK_SEMAPHORE_TYPE_TIMELINE : VK_SEMAPHORE_TYPE_BINARY;
    type.initialValue = 0;
    VkExportSemaphoreCreateInfo export_info =
        make<VkExportSemaphoreCreateInfo>(VK_STRUCTURE_TYPE_EXPORT_SEMAPHORE_CREATE_INFO);
    export_info.pNext = &type;
    export_info.handleTypes = VK_EXTERNAL_SEMAPHORE_HANDLE_TYPE_OPAQUE_FD_BIT;
    VkSemaphoreCreateInfo sci = make<VkSemaphoreCreateInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO);
    sci.pNext = &export_info;
    VkResult r = vkCreateSemaphore(c.device, &sci, nullptr, s);
    if (r != VK_SUCCESS)
        return *err = vk_text(timeline ? "vkCreateSemaphore (timeline)" : "vkCreateSemaphore", r), false;
    VkSemaphoreGetFdInfoKHR gi = make<VkSemaphoreGetFdInfoKHR>(VK_STRUCTURE_TYPE_SEMAPHORE_GET_FD_INFO_KHR);
    gi.semaphore = *s;
    gi.handleType = VK_EXTERNAL_SEMAPHORE_HANDLE_TYPE_OPAQUE_FD_BIT;
    r = c.get_semaphore_fd(c.device, &gi, fd);
    if (r != VK_SUCCESS) return *err = vk_text("vkGetSemaphoreFdKHR", r), false;
    return true;
}

struct SemaphoreValue {
    VkSemaphore semaphore;
    uint64_t value;  // ignored for binary semaphores
};

// Submits: wait (on the transfer stage), copy src -> dst, signal; then waits on the host.
inline bool copy_and_wait(const Context& c, VkBuffer src, VkBuffer dst, VkDeviceSize bytes,
                          const std::vector<SemaphoreValue>& waits, const std::vector<SemaphoreValue>& signals,
                          std::string* err) {
    VkCommandBufferAllocateInfo ai = make<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
    ai.commandPool = c.pool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VkCommandBuffer cb;
    VkResult r = vkAllocateCommandBuffers(c.device, &ai, &cb);
    if (r != VK_SUCCESS) return *err = vk_text("vkAllocateCommandBuffers", r), false;
    VkCommandBufferBeginInfo bi = make<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vkBeginCommandBuffer(cb, &bi);
    VkBufferCopy region{0, 0, bytes};
    vkCmdCopyBuffer(cb, src, dst, 1, &region);
    // Make the transfer's writes visible to the host once the fence signals.
    VkMemoryBarrier barrier = make<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr, 0,
                         nullptr);
    vkEndCommandBuffer(cb);
    std::vector<VkSemaphore> ws, ss;
    std::vector<uint64_t> wv, sv;
    std::vector<VkPipelineStageFlags> stages;
    for (const auto& w : waits) {
        ws.push_back(w.semaphore);
        wv.push_back(w.value);
        stages.push_back(VK_PIPELINE_STAGE_TRANSFER_BIT);
    }
    for (const auto& s : signals) {
        ss.push_back(s.semaphore);
        sv.push_back(s.value);
    }
    VkTimelineSemaphoreSubmitInfo ti =
        make<VkTimelineSemaphoreSubmitInfo>(VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO);
    ti.waitSemaphoreValueCount = uint32_t(wv.size());
    ti.pWaitSemaphoreValues = wv.data();
    ti.signalSemaphoreValueCount = uint32_t(sv.size());
    ti.pSignalSemaphoreValues = sv.data();
    VkSubmitInfo si = make<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    si.pNext = &ti;
    si.waitSemaphoreCount = uint32_t(ws.size());
    si.pWaitSemaphores = ws.data();
    si.pWaitDstStageMask = stages.data();
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cb;
    si.signalSemaphoreCount = uint32_t(ss.size());
    si.pSignalSemaphores = ss.data();
    VkFenceCreateInfo fci = make<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
    VkFence fence;
    vkCreateFence(c.device, &fci, nullptr, &fence);
    r = vkQueueSubmit(c.queue, 1, &si, fence);
    if (r == VK_SUCCESS) r = vkWaitForFences(c.device, 1, &fence, VK_TRUE, 10ull * 1000 * 1000 * 1000);
    vkDestroyFence(c.device, fence, nullptr);
    vkFreeCommandBuffers(c.device, c.pool, 1, &cb);
    if (r != VK_SUCCESS)
        return *err =
                   vk_text(r == VK_TIMEOUT ? "waiting for the Vulkan copy (10 s timeout: a semaphore never signalled?)"
                                           : "vkQueueSubmit / vkWaitForFences",
                           r),
               false;
    return true;
}

// ---- the round trip -----------------------------------------------------------------------
struct RoundTrip {
    bool ok = false;
    std::string error;
    std::string device_name;
    uint32_t frames = 0;
    uint32_t particles = 0;  // count at the last frame
    uint64_t mismatching_floats = 0;
    uint32_t draw_args_mismatches = 0;
    uint64_t transfers_in_copies = 0;  // library host<->device transfers made by step + copy + signal
};

// Runs frames round trips on world (a CUDA world with particles). auto_copy: PBF_COPY_ON_STEP +
// pbf_world_set_external_sync; else PBF_COPY_MANUAL + pbf_world_copy_to_external_buffer.
inline RoundTrip round_trip(pbf_world_id world, uint32_t frames, bool auto_copy, float dt = 1.0f / 60.0f) {
    RoundTrip out;
    out.frames = frames;
    std::string err;
    pbf_interop_info info;
    std::memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    pbf_world_info winfo;
    std::memset(&winfo, 0, sizeof winfo);
    winfo.struct_size = sizeof winfo;
    if (pbf_world_get_interop_info(world, &info) != PBF_OK || pbf_world_get_info(world, &winfo) != PBF_OK) {
        out.error = std::string("pbf info: ") + pbf_last_error_message();
        return out;
    }
    Context c;
    Buffer shared, host;
    VkSemaphore ready_bin = VK_NULL_HANDLE, ready_tl = VK_NULL_HANDLE, done_bin = VK_NULL_HANDLE,
                done_tl = VK_NULL_HANDLE;
    pbf_external_buffer_id buffer{0, 0};
    pbf_semaphore_id p_ready_bin{0, 0}, p_ready_tl{0, 0}, p_done_bin{0, 0}, p_done_tl{0, 0};
    const uint32_t capacity = winfo.max_particles;
    const VkDeviceSize particle_bytes = VkDeviceSize(capacity) * 16, bytes = particle_bytes + 16;
    std::vector<float> expected(size_t(capacity) * 4);
    auto run = [&]() -> bool {
        if (!init(c, info.device_uuid, &err)) return false;
        out.device_name = c.device_name;
        int fd = -1;
        if (!create_buffer(c, bytes, true, &shared, &fd, &err)) return false;
        if (!create_buffer(c, bytes, false, &host, nullptr, &err)) return false;
        pbf_external_buffer_desc d = pbf_external_buffer_desc_default();
        d.type = PBF_EXTERNAL_MEMORY_OPAQUE_FD;
        d.fd = fd;
        d.dedicated = 1;
        d.size_bytes = shared.size;
        d.capacity = capacity;
        d.mode = auto_copy ? PBF_COPY_ON_STEP : PBF_COPY_MANUAL;
        d.write_draw_args = 1;
        d.draw_args_offset_bytes = particle_bytes;
        if (pbf_world_import_external_buffer(world, &d, &buffer) != PBF_OK)
            return err = std::string("pbf_world_import_external_buffer: ") + pbf_last_error_message(), false;
        struct {
            VkSemaphore* vk;
            pbf_semaphore_id* id;
            bool timeline;
        } sems[] = {{&ready_bin, &p_ready_bin, false},
                    {&ready_tl, &p_ready_tl, true},
                    {&done_bin, &p_done_bin, false},
                    {&done_tl, &p_done_tl, true}};
        for (auto& s : sems) {
            int sfd = -1;
            if (!create_semaphore(c, s.timeline, s.vk, &sfd, &err)) return false;
            pbf_semaphore_desc sd = pbf_semaphore_desc_default();
            sd.type = s.timeline ? PBF_SEMAPHORE_VULKAN_TIMELINE_FD : PBF_SEMAPHORE_VULKAN_BINARY_FD;
            sd.fd = sfd;
            if (pbf_world_import_semaphore(world, &sd, s.id) != PBF_OK)
                return err = std::string("pbf_world_import_semaphore: ") + pbf_last_error_message(), false;
        }
        for (uint32_t f = 1; f <= frames; ++f) {
            const bool odd = f % 2 == 1;
            pbf_external_sync sync = pbf_external_sync_default();
            if (odd) {
                sync.wait_semaphore = p_done_tl;  // Vulkan's read of frame f-1 (value 0 at f = 1)
                sync.wait_value = f - 1;
                sync.signal_semaphore = p_ready_bin;
            } else {
                sync.wait_semaphore = p_done_bin;  // signalled by Vulkan at frame f-1
                sync.signal_semaphore = p_ready_tl;
                sync.signal_value = f;
            }
            uint64_t t0 = 0, t1 = 0;
            pbf_debug_get_transfer_count(&t0, nullptr);
            if (auto_copy && pbf_world_set_external_sync(world, buffer, &sync) != PBF_OK)
                return err = std::string("pbf_world_set_external_sync: ") + pbf_last_error_message(), false;
            if (pbf_world_step(world, dt) != PBF_OK)
                return err = std::string("pbf_world_step: ") + pbf_last_error_message(), false;
            if (!auto_copy && pbf_world_copy_to_external_buffer(world, buffer, &sync) != PBF_OK)
                return err = std::string("pbf_world_copy_to_external_buffer: ") + pbf_last_error_message(), false;
            pbf_debug_get_transfer_count(&t1, nullptr);
            out.transfers_in_copies += t1 - t0;
            std::vector<SemaphoreValue> waits{odd ? SemaphoreValue{ready_bin, 0} : SemaphoreValue{ready_tl, f}};
            std::vector<SemaphoreValue> signals{{done_tl, f}};
            if (odd) signals.push_back({done_bin, 0});  // waited on by frame f+1's copy
            if (!copy_and_wait(c, shared.buffer, host.buffer, bytes, waits, signals, &err)) return false;
            // Compare with copy-out (the world has not changed since the copy).
            uint32_t count = 0, written = 0;
            if (pbf_world_get_particle_count(world, &count) != PBF_OK ||
                pbf_world_copy_positions(world, expected.data(), capacity, &written) != PBF_OK)
                return err = std::string("copy-out: ") + pbf_last_error_message(), false;
            const float* got = static_cast<const float*>(host.mapped);
            uint32_t args[4];
            std::memcpy(args, static_cast<const char*>(host.mapped) + particle_bytes, sizeof args);
            if (args[0] != count || args[1] != 1 || args[2] != 0 || args[3] != 0) ++out.draw_args_mismatches;
            for (size_t i = 0; i < size_t(written) * 4; ++i)
                if (std::memcmp(&got[i], &expected[i], sizeof(float)) != 0) ++out.mismatching_floats;
            out.particles = count;
        }
        return true;
    };
    out.ok = run();
    out.error = err;
    // The library's imports go first (they wait for the world's stream), then Vulkan's objects.
    if (buffer.generation) pbf_world_release_external_buffer(world, buffer);
    for (pbf_semaphore_id id : {p_ready_bin, p_ready_tl, p_done_bin, p_done_tl})
        if (id.generation) pbf_world_release_semaphore(world, id);
    if (c.device) {
        vkDeviceWaitIdle(c.device);
        for (VkSemaphore s : {ready_bin, ready_tl, done_bin, done_tl})
            if (s) vkDestroySemaphore(c.device, s, nullptr);
        destroy(c, shared);
        destroy(c, host);
    }
    shutdown(c);
    if (out.ok && (out.mismatching_floats || out.draw_args_mismatches)) {
        out.ok = false;
        out.error = "the Vulkan buffer differs from pbf_world_copy_positions";
    }
    return out;
}

}  // namespace pbf_vk
