// Reading the contact laws of a scenario table by their traits (contact/law_traits.hpp,
// docs/contact-laws.md): every law's keys with the same kinds, defaults and messages.
#pragma once
#include <span>
#include <string_view>

#include "tsubu/contact/law.hpp"
#include "tsubu/scenario/reader.hpp"

namespace tsubu {

// The values of `law`'s keys that the table gives (the others take their defaults when the
// law is built), each checked against its kind. `role` ("normal" or "tangential") names the
// key that chose the law ("rolling" too), for the message of a required key that is missing.
LawValues read_law_keys(Section& s, const LawTraits& law, std::string_view role);

// A [contact.default] or [[contact.pairs]] entry: the laws chosen among `normals` and
// `tangentials` (the registry by default) and kRollingLaws, refused with an integrator they do not allow,
// the generic keys, the chosen laws' keys, and the keys of the other laws refused by name
// ("is used only with normal = ...").
ContactSpec read_contact_spec(Section& s, std::string_view integrator, std::span<const LawTraits> normals = kNormalLaws,
                              std::span<const LawTraits> tangentials = kTangentialLaws);

}  // namespace tsubu
