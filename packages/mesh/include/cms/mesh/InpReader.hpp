// Abaqus / CalculiX input decks (.inp) read as meshes: the nodes, the
// elements and the node and element sets of a deck, so that a CalculiX or
// Abaqus user runs the mesh they already have (doc/user-guide.md, "Meshes").
// Everything that is not mesh (materials, sections, boundary conditions,
// steps) comes from the scene; the reader skips it and says so in
// Mesh::notes.
#pragma once

#include <string>

#include "cms/mesh/Mesh.hpp"

namespace cms::mesh {

/// Reads the mesh of an Abaqus/CalculiX input deck:
///  - `*NODE` (NSET=; SYSTEM=R only), node ids sparse and in any order;
///  - `*ELEMENT, TYPE=` C3D4, C3D8, C3D8R, C3D8I, C3D10, C3D20, C3D20R, C3D15
///    (solids) and B31 (2-node beams), ELSET=; a data line ending with a
///    comma continues on the next one while the element lacks nodes; the
///    nodes are reordered from the deck's (Abaqus) order to the project's
///    (Gmsh's, see CellType) and the deck's type name is kept in
///    CellBlock::elementName (C3D8R/C3D20R: reduced integration, C3D8I:
///    incompatible modes, for the model to honour);
///  - `*NSET, NSET=` / `*ELSET, ELSET=` with ids, names of sets defined
///    above, or GENERATE (first, last[, step]: the defined ids of that range);
///    `*NSET, ELSET=` (the nodes of an element set); a set named again adds
///    to itself;
///  - `*INCLUDE, INPUT=` (relative to the including file, read in place;
///    a file that includes itself, directly or not, is refused), and INPUT=
///    on the keywords above (their data lines from that file).
/// Keywords, parameter names and set names are case-insensitive (a set keeps
/// the spelling of its first definition), `**` starts a comment line, blank
/// lines are ignored, a keyword line ending with a comma continues. Element
/// sets become groups of their cells (dimension 3, or 1 for beams), node sets
/// groups of dimension 0 (one Point1 cell per node); a name may be both (see
/// Mesh::nodeSet). Every other keyword and its data lines are skipped with a
/// note; keywords that would move or generate nodes (*NGEN, *NCOPY, *SYSTEM,
/// *PART, *INSTANCE, ...) are refused rather than silently misread.
/// Throws cms::InputError "file:line: what is wrong" (a file included from
/// another also naming where it was included): a bad number or id (ids are
/// 1 .. 2^31 - 1), a non-finite coordinate, an id defined twice, an element
/// type not in the list above (the list is given), a wrong node count for the
/// type, an element on an undefined node, a set naming an undefined id or
/// set, GENERATE with a zero, negative or empty range, an *INCLUDE that
/// cannot be opened or is cyclic, no nodes.
Mesh readInp(const std::string& path);

}  // namespace cms::mesh
