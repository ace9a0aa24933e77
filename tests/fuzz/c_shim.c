/* Calls the C ABI the way C code can and C++ code cannot without undefined behaviour: with an
 * enum argument holding any int (C enums are plain integers). */
#include <pbf_c_api.h>

const char* pbf_fuzz_result_string(int32_t value) { return pbf_result_string((pbf_result)value); }
