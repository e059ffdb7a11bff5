#include "ua/types/variant.hpp"

namespace skillcell::ua {

Variant Variant::array(BuiltinType type, std::vector<Scalar> elements,
                       std::vector<std::int32_t> dimensions) {
    Variant v;
    v.isArray_ = true;
    v.arrayType_ = type;
    v.elements_ = std::move(elements);
    v.dimensions_ = std::move(dimensions);
    return v;
}

}  // namespace skillcell::ua
