#include "cms/core/ParameterReading.hpp"

#include <cmath>
#include <sstream>

#include "cms/core/Error.hpp"

namespace cms {

using Teuchos::ParameterList;

/// The names of a valid list's entries, for messages.
std::string namesOf(const ParameterList& valid) {
  std::ostringstream os;
  bool first = true;
  for (auto it = valid.begin(); it != valid.end(); ++it) {
    os << (first ? "" : ", ") << '"' << valid.name(it) << '"';
    first = false;
  }
  return os.str();
}

/// Every key of `p` must be a key of `valid`, with a sublist exactly where
/// valid has one.
void checkKeys(const ParameterList& p, const ParameterList& valid, const std::string& path) {
  for (auto it = p.begin(); it != p.end(); ++it) {
    const std::string& key = p.name(it);
    CMS_INPUT_CHECK(!valid.isParameter(key), path << ": unknown key \"" << key << "\"; valid keys are "
                                                  << namesOf(valid));
    CMS_INPUT_CHECK(p.isSublist(key) != valid.isSublist(key),
                    path << "/" << key << ": " << (valid.isSublist(key) ? "must be a list of entries"
                                                                       : "must be a value, not a list"));
  }
}

void validateOptions(ParameterList& p, const ParameterList& valid, const std::string& owner) {
  checkKeys(p, valid, owner);
  try {
    p.validateParametersAndSetDefaults(valid);
  } catch (const std::exception& e) {
    throw InputError(owner + ": " + e.what());
  }
}

void promoteIntegers(ParameterList& p, const ParameterList& valid) {
  for (auto it = p.begin(); it != p.end(); ++it) {
    const std::string& key = p.name(it);
    if (!valid.isParameter(key)) continue;  // unknown keys are the validation's to name
    if (p.isSublist(key) && valid.isSublist(key)) {
      promoteIntegers(p.sublist(key), valid.sublist(key));
    } else if (p.isType<int>(key) && valid.isType<double>(key)) {
      p.set(key, static_cast<double>(p.get<int>(key)));
    }
  }
}

double getNumber(const ParameterList& p, const std::string& key, const std::string& path,
                 std::optional<double> fallback) {
  if (!p.isParameter(key)) {
    CMS_INPUT_CHECK(!fallback, path << ": missing required key \"" << key << "\"");
    return *fallback;
  }
  double v = 0.0;
  if (p.isType<double>(key)) v = p.get<double>(key);
  else if (p.isType<int>(key)) v = p.get<int>(key);
  else if (p.isType<long long>(key)) v = static_cast<double>(p.get<long long>(key));
  else CMS_INPUT_CHECK(true, path << "/" << key << ": must be a number");
  CMS_INPUT_CHECK(!std::isfinite(v), path << "/" << key << " = " << v << " must be finite");
  return v;
}

std::string getString(const ParameterList& p, const std::string& key, const std::string& path,
                      std::optional<std::string> fallback) {
  if (!p.isParameter(key)) {
    CMS_INPUT_CHECK(!fallback, path << ": missing required key \"" << key << "\"");
    return *fallback;
  }
  CMS_INPUT_CHECK(!p.isType<std::string>(key), path << "/" << key << ": must be a string");
  return p.get<std::string>(key);
}

bool getBool(const ParameterList& p, const std::string& key, const std::string& path, bool fallback) {
  if (!p.isParameter(key)) return fallback;
  CMS_INPUT_CHECK(!p.isType<bool>(key), path << "/" << key << ": must be true or false");
  return p.get<bool>(key);
}

std::vector<double> getNumbers(const ParameterList& p, const std::string& key, const std::string& path,
                               std::size_t size, std::optional<std::vector<double>> fallback) {
  if (!p.isParameter(key)) {
    CMS_INPUT_CHECK(!fallback, path << ": missing required key \"" << key << "\"");
    return *fallback;
  }
  std::vector<double> v;
  if (p.isType<Teuchos::Array<double>>(key)) {
    const auto& a = p.get<Teuchos::Array<double>>(key);
    v.assign(a.begin(), a.end());
  } else if (p.isType<Teuchos::Array<int>>(key)) {
    const auto& a = p.get<Teuchos::Array<int>>(key);
    v.assign(a.begin(), a.end());
  } else {
    CMS_INPUT_CHECK(true, path << "/" << key << ": must be a list of " << size << " numbers, e.g. [0, 0, 1]");
  }
  CMS_INPUT_CHECK(v.size() != size, path << "/" << key << ": has " << v.size() << " numbers, needs " << size);
  for (double x : v) CMS_INPUT_CHECK(!std::isfinite(x), path << "/" << key << ": entry " << x << " must be finite");
  return v;
}


}  // namespace cms
