// Tests that fit models to data or run Jets through the dynamics shrink their
// work where the build is slow (unoptimised, or under the sanitizers, which
// check memory safety; the release run checks the statistics).
#pragma once

#if defined(__SANITIZE_ADDRESS__) || !defined(NDEBUG)
constexpr bool kSlowBuild = true;
#else
constexpr bool kSlowBuild = false;
#endif
