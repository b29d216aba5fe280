// A thing of one of several kinds (a material, a light): the kind's own type, with its own
// fields, held in a std::variant. visit_kind is the one switch over the kinds: every
// operation that differs by kind goes through it, once per packet of points of one material
// or light, and calls the kind's own function (no per-lane dispatch, no virtual calls).
#pragma once

#include <cstddef>
#include <variant>

#include "core/simd/target.h"

namespace patina {

template <class... Kinds>
struct OneOfKinds {
    std::variant<Kinds...> model;

    template <class Kind>
    bool is() const {
        return std::holds_alternative<Kind>(model);
    }
    template <class Kind>
    const Kind& as() const {
        return *std::get_if<Kind>(&model);
    }
};

// visitor(x's kind, as its own type): a switch on the kind, inlined.
template <class Visitor, class... Kinds>
PATINA_INLINE decltype(auto) visit_kind(const OneOfKinds<Kinds...>& x, Visitor&& visitor) {
    constexpr size_t count = sizeof...(Kinds);
    static_assert(count <= 8, "a case below for each kind");
    switch (x.model.index()) {
        case 0: return visitor(*std::get_if<0>(&x.model));
        case 1: if constexpr (count > 1) return visitor(*std::get_if<1>(&x.model)); break;
        case 2: if constexpr (count > 2) return visitor(*std::get_if<2>(&x.model)); break;
        case 3: if constexpr (count > 3) return visitor(*std::get_if<3>(&x.model)); break;
        case 4: if constexpr (count > 4) return visitor(*std::get_if<4>(&x.model)); break;
        case 5: if constexpr (count > 5) return visitor(*std::get_if<5>(&x.model)); break;
        case 6: if constexpr (count > 6) return visitor(*std::get_if<6>(&x.model)); break;
        case 7: if constexpr (count > 7) return visitor(*std::get_if<7>(&x.model)); break;
    }
    __builtin_unreachable();  // a variant always holds one of its kinds
}

}  // namespace patina
