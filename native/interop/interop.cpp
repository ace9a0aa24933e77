// The world's interop state, kept as the world's attachment (built in every configuration; the
// CUDA implementation is interop_cuda.cu, the refusal of a CPU-only build interop_stub.cpp).
#include "interop.h"

namespace pbf {

Status Interop::of(World& world, Interop** out) {
    if (Interop* io = existing(world)) {
        *out = io;
        return Status{};
    }
    Status st;
    std::unique_ptr<Interop> interop = create(world, &st);
    if (!interop) return st;
    *out = interop.get();
    world.set_attachment(std::move(interop));
    return Status{};
}

// A world's only attachment is the Interop that of() gave it.
Interop* Interop::existing(World& world) { return static_cast<Interop*>(world.attachment()); }

}  // namespace pbf
