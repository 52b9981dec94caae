// What libcorebox.so exports: the API only. The library is built with hidden visibility, so every
// internal symbol stays inside it; COREBOX_API marks the classes and functions a program may use (and
// the exceptions, whose type information must be one across the library boundary for catch to work).
#pragma once

#if defined(__GNUC__) || defined(__clang__)
#define COREBOX_API __attribute__((visibility("default")))
#else
#define COREBOX_API
#endif
