// Objects addressed by {index, generation} handles: a destroyed slot bumps its generation, so
// an old handle no longer matches and is refused instead of reaching a reused object.
#pragma once
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
        if (++s.generation == 0) s.generation = 1;  // 0 is never a valid generation
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
    struct Slot {
        std::optional<T> value;
        uint32_t generation = 1;
        bool alive = false;
    };
    std::vector<Slot> slots_;
    std::vector<uint32_t> free_;
    size_t alive_ = 0;
};

}  // namespace pbf
