// Reading a user's Teuchos::ParameterList (a scene or model from YAML) key by
// key, so that a misspelt key or a value of the wrong type is reported with
// its full path ("Scene/Substructures/boom/Spin/Rate: must be a number")
// before anything is computed. Numbers may be given as integers or reals
// (YAML writes 7850, not 7850.0). Every failure throws cms::InputError.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

namespace cms {

/// The names of a valid list's entries, quoted and comma-separated (for messages).
std::string namesOf(const Teuchos::ParameterList& valid);

/// Every key of `p` must be a key of `valid`, with a sublist exactly where
/// valid has one; the message lists the valid keys.
void checkKeys(const Teuchos::ParameterList& p, const Teuchos::ParameterList& valid, const std::string& path);

/// A class's options checked against its valid list: checkKeys (a message
/// naming every valid key), then Teuchos' validation (types, validators),
/// defaults filled in; any failure a cms::InputError starting with `owner`.
void validateOptions(Teuchos::ParameterList& p, const Teuchos::ParameterList& valid, const std::string& owner);

/// A finite number (int or double), or `fallback` when absent (required when none).
/// Every integer of `p` whose key `valid` declares a double becomes that
/// double, through nested lists: a scene's "Cutoff Frequency: 1500" is a
/// frequency, not a type error (YAML reads 1500 as an integer).
void promoteIntegers(Teuchos::ParameterList& p, const Teuchos::ParameterList& valid);

double getNumber(const Teuchos::ParameterList& p, const std::string& key, const std::string& path,
                 std::optional<double> fallback = std::nullopt);
std::string getString(const Teuchos::ParameterList& p, const std::string& key, const std::string& path,
                      std::optional<std::string> fallback = std::nullopt);
bool getBool(const Teuchos::ParameterList& p, const std::string& key, const std::string& path, bool fallback);
/// Exactly `size` finite numbers ([0, 0, 1]).
std::vector<double> getNumbers(const Teuchos::ParameterList& p, const std::string& key, const std::string& path,
                               std::size_t size, std::optional<std::vector<double>> fallback);

}  // namespace cms
