// Objects addressed by {index, generation} handles: a destroyed slot bumps its generation, so
// an old handle no longer matches and is refused instead of reaching a reused object.
#pragma once
#include <atomic>
#include <cstdint>
#include <optional>
#include <vector>

namespace pbf {

template <class T>
class SlotTable {
public:
    struct Handle {
        uint32_t index, generation;
    };

    Handle insert(T value) {
        uint32_t index;
        if (!free_.empty()) {
            index = free_.back();
            free_.pop_back();
        } else {
            index = static_cast<uint32_t>(slots_.size());
            slots_.push_back(Slot{});
        }
        Slot& s = slots_[index];
        s.value = std::move(value);
        s.alive = true;
        s.generation = next_generation();
        ++alive_;
        return Handle{index, s.generation};
    }

    // nullptr for a zeroed, forged or stale handle.
    T* find(uint32_t index, uint32_t generation) {
        if (index >= slots_.size()) return nullptr;
        Slot& s = slots_[index];
        return (s.alive && s.generation == generation && generation != 0) ? &*s.value : nullptr;
    }

    bool erase(uint32_t index, uint32_t generation) {
        if (!find(index, generation)) return false;
        Slot& s = slots_[index];
        s.value.reset();
        s.alive = false;
        free_.push_back(index);
        --alive_;
        return true;
    }

    size_t size() const { return alive_; }

    template <class F>
    void for_each(F&& f) {
        for (Slot& s : slots_)
            if (s.alive) f(*s.value);
    }

private:
    // Generations come from one process-wide counter (never 0), so a handle is refused by every
    // table but the one that issued it, and by that one once the object is gone.
    static uint32_t next_generation() {
        static std::atomic<uint32_t> counter{1};
        uint32_t g = counter.fetch_add(1, std::memory_order_relaxed);
        if (g == 0) g = counter.fetch_add(1, std::memory_order_relaxed);
        return g;
    }
    struct Slot {
        std::optional<T> value;
        uint32_t generation = 0;
        bool alive = false;
    };
    std::vector<Slot> slots_;
    std::vector<uint32_t> free_;
    size_t alive_ = 0;
};

}  // namespace pbf
