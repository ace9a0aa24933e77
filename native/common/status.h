// A result code with its message, the currency of every layer below the C ABI.
#pragma once
#include <string>
#include <utility>

#include "pbf_c_api.h"

namespace pbf {

// ok() when code == PBF_OK.
struct Status {
    pbf_result code = PBF_OK;
    std::string message;
    bool ok() const { return code == PBF_OK; }
    static Status error(pbf_result c, std::string m) { return Status{c, std::move(m)}; }
};

}  // namespace pbf
