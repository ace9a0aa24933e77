// The process-wide table of worlds: handles in, locked worlds out.
#include <mutex>
#include <string>

#include "../common/slot_table.h"
#include "api_common.h"

namespace {
std::mutex g_worlds_mutex;
pbf::SlotTable<std::shared_ptr<pbf::api::WorldEntry>> g_worlds;
}  // namespace

namespace pbf::api {

pbf_world_id insert_world(std::unique_ptr<World> world) {
    auto entry = std::make_shared<WorldEntry>();
    entry->world = std::move(world);
    std::lock_guard<std::mutex> lock(g_worlds_mutex);
    const auto h = g_worlds.insert(entry);
    return pbf_world_id{h.index, h.generation};
}

std::shared_ptr<WorldEntry> remove_world(pbf_world_id id) {
    std::lock_guard<std::mutex> lock(g_worlds_mutex);
    std::shared_ptr<WorldEntry> entry;
    if (auto* e = g_worlds.find(id.index, id.generation)) entry = *e;
    if (entry) g_worlds.erase(id.index, id.generation);
    return entry;
}

WorldLock::WorldLock(const char* fn, pbf_world_id id, bool quiet) {
    {
        std::lock_guard<std::mutex> lock(g_worlds_mutex);
        if (auto* e = g_worlds.find(id.index, id.generation)) entry_ = *e;
    }
    if (entry_) {
        lock_ = std::unique_lock<std::mutex>(entry_->mutex);
        if (!entry_->world) {
            // Destroyed meanwhile: this may be the entry's last reference, so unlock before
            // letting it go (the mutex goes with it).
            lock_.unlock();
            entry_.reset();
        }
    }
    if (!entry_) {
        const std::string message = std::string(fn) + ": world {" + std::to_string(id.index) + ", " +
                                    std::to_string(id.generation) +
                                    "} is not a live world (destroyed or never created)";
        result_ = quiet ? PBF_ERROR_INVALID_HANDLE : fail(PBF_ERROR_INVALID_HANDLE, message);
    }
}

}  // namespace pbf::api
