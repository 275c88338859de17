// The interface between Mesh.cpp and the Gmsh reader module (GmshReader.cpp,
// built as cms-gmsh-reader.so beside the .geo mesher in libexec/cms and
// loaded on first use): one C entry point through which no exception passes.
#pragma once

#include <string>

#include "cms/mesh/Mesh.hpp"

namespace cms::mesh::detail {

/// Called between the nodes and the cells (the reader's checks in their
/// order): Mesh.cpp's check for coincident nodes. May throw InputError.
using GmshNodeCheck = void (*)(const Mesh&);

enum GmshReadStatus : int { kGmshReadOk = 0, kGmshReadInputError = 1, kGmshReadOutOfMemory = 2 };

/// cms_gmsh_read_msh(path, source, mesh, message, checkNodes): reads the .msh
/// at `path` into `*mesh`, messages naming `source`; on kGmshReadInputError
/// `*message` is the whole message.
using GmshReadMsh = int (*)(const char*, const char*, Mesh*, std::string*, GmshNodeCheck);
inline constexpr const char* kGmshReadMshSymbol = "cms_gmsh_read_msh";
inline constexpr const char* kGmshReaderModule = "cms-gmsh-reader.so";

}  // namespace cms::mesh::detail
