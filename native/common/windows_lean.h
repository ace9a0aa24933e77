// <windows.h> without min/max macros (they break std::min and std::max) and without the rarely
// used APIs it pulls in by default; Windows builds only.
#pragma once
#if defined(_WIN32)
#ifndef NOMINMAX
#define NOMINMAX
#endif
#ifndef WIN32_LEAN_AND_MEAN
#define WIN32_LEAN_AND_MEAN
#endif
#include <windows.h>
#endif
