#pragma once
// TESSERA_INLINE: how the larger non-template functions of tessera are compiled.
//
// Header-only (the default): TESSERA_INLINE is `inline` and every header includes its
// definitions (impl/<header>.ipp) at its end, so including a header is all a program needs.
//
// Separate compilation (TESSERA_SEPARATE_COMPILATION defined): those functions are only declared
// by their headers and defined once in the tessera::instances library (src/separate.cpp compiles
// every impl/*.ipp), so a scene's unit neither parses nor optimises them again. Linking
// tessera::instances defines TESSERA_SEPARATE_COMPILATION for every unit of the program (a
// PUBLIC compile definition of the target), so one program is compiled in one mode only.
// Templates and the short helpers of hot loops stay in the headers in both modes.

/// `inline` in the header-only build, empty under TESSERA_SEPARATE_COMPILATION.
#ifdef TESSERA_SEPARATE_COMPILATION
#define TESSERA_INLINE
#else
#define TESSERA_INLINE inline
#endif
