// BTOCL_API marks what a shared build of the library exports: the public API alone. The rest of
// the library is built with hidden visibility; a static build exports everything anyway.
#pragma once

#if defined(__GNUC__) || defined(__clang__)
#define BTOCL_API __attribute__((visibility("default")))
#else
#define BTOCL_API
#endif
