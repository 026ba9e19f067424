#pragma once
// The one list of contact laws. Each law is one self-contained struct in its own file (its pair
// coefficients made from the scene, force kernel, elastic energy, lever arm, time-step bound,
// static overlap, scene keys and cached-bed key fields); the engine instantiates its pair and wall
// loops once per law, so no contact ever branches on which law is in use. To add a law, write its
// file after contact/hertz_mindlin.hpp, include it here and add it to `Laws` below.
#include <string>
#include <type_traits>
#include <variant>

#include "contact/hertz_mindlin.hpp"
#include "contact/rapaport2007.hpp"
#include "contact/yu2022.hpp"
#include "scene/law_registry.hpp"
#include "scene/scene.hpp"

namespace tumble::contact {

template <class... L>
struct LawList {};
using Laws = LawList<Yu2022Law, Rapaport2007Law, HertzMindlinLaw>;  // <- the registration line

// The coefficients of one law for every species pair and species-wall pair, made once per scene.
template <class Law>
struct Tables {
  typename Law::Pair pair[2][2];  // [species a][species b]
  typename Law::Pair wall[2];     // [species]

  static Tables make(const Scene& s) {
    Tables t;
    for (int a = 0; a < 2; ++a) {
      for (int b = 0; b < 2; ++b) t.pair[a][b] = Law::make_pair(s, a, b);
      t.wall[a] = Law::make_wall(s, a);
    }
    return t;
  }
};

// The tables of whichever law a scene selected.
template <class List>
struct AnyTablesOf;
template <class... L>
struct AnyTablesOf<LawList<L...>> {
  using type = std::variant<Tables<L>...>;
};
using AnyTables = AnyTablesOf<Laws>::type;

// A law as a value, for generic lambdas: with_law(s, [](auto tag) { using Law = typename
// decltype(tag)::type; ... }).
template <class Law>
struct LawTag {
  using type = Law;
};

namespace detail {
template <class F, class... L>
void with_law(const std::string& name, F&& f, LawList<L...>) {
  bool found = false;
  ((!found && name == L::kName ? (found = true, f(LawTag<L>{}), 0) : 0), ...);
  if (!found) (void)contact_law(name);  // throws: the name is not a law
}
template <class... L>
void register_all(LawList<L...>) {
  (register_contact_law(L::spec()), ...);
}
}  // namespace detail

// Calls f(LawTag<Law>{}) for the law the scene selected (contact.law): once per scene, never per
// contact.
template <class F>
void with_law(const Scene& s, F&& f) {
  detail::with_law(s.law, f, Laws{});
}

// Registers every law with the scene layer (scene/law_registry.hpp). Programs and tests call it
// once before reading a scene (app/main.cpp, tests/register_laws.cpp); calling it again is
// harmless.
inline void register_laws() { detail::register_all(Laws{}); }

}  // namespace tumble::contact
