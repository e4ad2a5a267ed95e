// assert.hpp — CDP_ASSERT for programming errors (never for user input).
// Active in debug builds only; user input errors are ConfigError, numerical trouble
// goes into the step report.
#pragma once

#include <cstdio>
#include <cstdlib>

#ifdef NDEBUG
#define CDP_ASSERT(cond, message) static_cast<void>(0)
#else
#define CDP_ASSERT(cond, message)                                                           \
  do {                                                                                      \
    if (!(cond)) {                                                                          \
      std::fprintf(stderr, "%s:%d: assertion failed: %s (%s)\n", __FILE__, __LINE__, #cond, \
                   message);                                                                \
      std::abort();                                                                         \
    }                                                                                       \
  } while (false)
#endif
