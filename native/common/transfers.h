// The library's own host<->device copies, counted process-wide: each copy between host and
// device memory made by an executor counts once, so tests can show that a path (the render
// path, a mapping) adds none. Read by pbf_debug_get_transfer_count.
#pragma once
#include <cstdint>

namespace pbf {

void note_host_device_transfer(uint64_t bytes);
void host_device_transfers(uint64_t* transfers, uint64_t* bytes);

}  // namespace pbf
