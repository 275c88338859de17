// Internal to the scene package: YAML text to a ParameterList by yaml-cpp.
#pragma once

#include <string>

#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>

namespace cms::scene::detail {

/// The text's one top-level mapping as a ParameterList named by its key.
/// Throws cms::InputError "path:line:column: not a valid scene file (...)"
/// for YAML it cannot read or values no scene key takes (nested lists).
Teuchos::RCP<Teuchos::ParameterList> parseYaml(const std::string& text, const std::string& path);

}  // namespace cms::scene::detail
