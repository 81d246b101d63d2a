// The registry of interface laws (see interface_law.hpp).
#include "laws/interface_law.hpp"

#include <algorithm>

#include "config/simulation_config.hpp"

namespace slipstrip {

// Each law's factory, defined in its own file.
#define SLIPSTRIP_INTERFACE_LAW(law) \
  std::unique_ptr<InterfaceLaw> make_##law##_law(const InterfaceSetup& setup);
#include "config/interface_laws.inc"
#undef SLIPSTRIP_INTERFACE_LAW

InterfaceLawRegistry builtin_interface_laws() {
  InterfaceLawRegistry laws;
#define SLIPSTRIP_INTERFACE_LAW(law) laws.add({#law, &make_##law##_law});
#include "config/interface_laws.inc"
#undef SLIPSTRIP_INTERFACE_LAW
  return laws;
}

void integrate_slip(InterfaceFields& fields, double dt) {
  const std::size_t n = fields.slip.size();
  for (std::size_t i = 0; i < n; ++i)
    fields.slip[i] += 0.5 * dt * (fields.previous_slip_rate[i] + fields.slip_rate[i]);
}

void InterfaceLawRegistry::add(InterfaceLawEntry entry) {
  if (find(entry.name) != nullptr)
    throw std::invalid_argument("interface law '" + std::string(entry.name) +
                                "' is registered twice");
  entries_.push_back(entry);
}

const InterfaceLawEntry* InterfaceLawRegistry::find(std::string_view name) const {
  const auto it = std::find_if(entries_.begin(), entries_.end(),
                               [name](const InterfaceLawEntry& e) { return e.name == name; });
  return it == entries_.end() ? nullptr : &*it;
}

std::vector<std::string_view> InterfaceLawRegistry::names() const {
  std::vector<std::string_view> out;
  for (const auto& e : entries_) out.push_back(e.name);
  return out;
}

std::unique_ptr<InterfaceLaw> InterfaceLawRegistry::make(const InterfaceSetup& setup) const {
  const std::string_view name = setup.config.interface.law.name;
  if (const InterfaceLawEntry* entry = find(name)) return entry->make(setup);
  std::string list;
  for (const auto& e : entries_) list += (list.empty() ? "" : ", ") + std::string(e.name);
  throw std::invalid_argument("interface.law = '" + std::string(name) +
                              "' is not a registered interface law: expected one of " + list);
}

}  // namespace slipstrip
