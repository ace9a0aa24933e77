// Text into the fixed char arrays of the C ABI's structs.
#pragma once
#include <cstddef>
#include <cstring>
#include <string>

namespace pbf {

// dst := text, cut to fit, zero-padded and always terminated.
template <size_t N>
void copy_text(char (&dst)[N], const std::string& text) {
    static_assert(N > 0, "room for the terminator");
    std::strncpy(dst, text.c_str(), N - 1);
    dst[N - 1] = '\0';
}

}  // namespace pbf
