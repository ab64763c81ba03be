#pragma once
/// major version
#define TESSERA_VERSION_MAJOR 0
/// minor version
#define TESSERA_VERSION_MINOR 1
/// patch version
#define TESSERA_VERSION_PATCH 0
/// "major.minor.patch"
#define TESSERA_VERSION_STRING "0.1.0"
