// Mode shapes for ParaView: one VTK unstructured grid (.vtu, ASCII XML) per
// mode holding every substructure's mesh in the structure's axes (frame
// elements as lines, solids as their cells, rigid rotors as a vertex at their
// centre), with the mode's displacement as point data (real and imaginary
// parts; rotations too, where a node has them), and a .pvd collection of
// all modes (doc/user-guide.md, "Mode shapes").
#pragma once

#include <string>
#include <vector>

#include "cms/io/OutputFiles.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

namespace cms::io {

/// Collective; rank 0 stages <directory>/<name>-mode-<k>.vtu (k from 1) and
/// <name>-modes.pvd in `files` (written, with the run's other files, by
/// files.commit(comm)). Returns the files staged (rank 0; empty elsewhere).
std::vector<std::string> writeModeShapes(OutputFiles& files, const synthesis::AssembledStructure& structure,
                                         const synthesis::SynthesizedStructure& synthesis,
                                         const synthesis::StructureModes& modes, const std::string& directory,
                                         const std::string& name);

}  // namespace cms::io
