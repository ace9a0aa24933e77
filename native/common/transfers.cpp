// The library's count of its own host<->device copies (transfers.h).
#include "transfers.h"

#include <atomic>

namespace pbf {
namespace {
std::atomic<uint64_t> g_transfers{0};
std::atomic<uint64_t> g_transfer_bytes{0};
}  // namespace

void note_host_device_transfer(uint64_t bytes) {
    g_transfers.fetch_add(1, std::memory_order_relaxed);
    g_transfer_bytes.fetch_add(bytes, std::memory_order_relaxed);
}

void host_device_transfers(uint64_t* transfers, uint64_t* bytes) {
    *transfers = g_transfers.load(std::memory_order_relaxed);
    *bytes = g_transfer_bytes.load(std::memory_order_relaxed);
}

}  // namespace pbf
