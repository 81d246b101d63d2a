#pragma once
// Which interface law a run uses ([interface] law), and the names of the
// built-in laws.  The config only needs the names; the laws themselves (their
// interface, registry and implementations) live in laws/, above the config.
#include <string_view>

namespace slipstrip {

// A law's registered name.  A value type with the built-in laws as named
// constants (InterfaceLawName::free), so adding a law needs no enumerator.  `name`
// refers to static storage (a string literal or a registry entry's name).
struct InterfaceLawName {
  std::string_view name;
  static const InterfaceLawName rate_and_state;   // the paper's friction (default)
  static const InterfaceLawName prescribed_slip;  // slip(x,t) imposed (verification)
  static const InterfaceLawName free;             // traction-free plus an imposed stress pulse (verification)
  friend bool operator==(const InterfaceLawName&, const InterfaceLawName&) = default;
};
inline constexpr InterfaceLawName InterfaceLawName::rate_and_state{"rate_and_state"};
inline constexpr InterfaceLawName InterfaceLawName::prescribed_slip{"prescribed_slip"};
inline constexpr InterfaceLawName InterfaceLawName::free{"free"};

// The built-in laws' names in registration order (config/interface_laws.inc):
// the values [interface] law accepts.
inline constexpr std::string_view kBuiltinInterfaceLawNames[] = {
#define SLIPSTRIP_INTERFACE_LAW(law) #law,
#include "config/interface_laws.inc"
#undef SLIPSTRIP_INTERFACE_LAW
};

}  // namespace slipstrip
