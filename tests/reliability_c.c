/* C callers of the ABI for test_reliability.cpp: C code may pass an enum argument holding any
 * int (C enums are plain integers), which C++ test code cannot do without undefined behaviour. */
#include <pbf_c_api.h>

const char* pbf_test_result_string_of_int(int value) { return pbf_result_string((pbf_result)value); }
