// Small helpers of the command-line tools (tools/bench, tools/paper, tools/frames), public C
// API only: comma-separated option lists, and the world's info read with struct_size filled.
#pragma once
#include <cstring>
#include <string>
#include <vector>

#include "pbf_c_api.h"

namespace tool {

// "a,b,,c" -> {"a", "b", "", "c"}; "" -> {""}.
inline std::vector<std::string> split_list(const std::string& s) {
    std::vector<std::string> out;
    size_t start = 0;
    while (start <= s.size()) {
        const size_t comma = s.find(',', start);
        out.push_back(s.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return out;
}

// pbf_world_get_info into a zeroed struct of this header's size.
inline pbf_result read_info(pbf_world_id w, pbf_world_info* info) {
    std::memset(info, 0, sizeof *info);
    info->struct_size = sizeof *info;
    return pbf_world_get_info(w, info);
}

}  // namespace tool
