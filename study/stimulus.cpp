#include "stimulus.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gt::study {

const std::vector<ParameterInfo>& parameters() {
    // Ranges are the render command's: the thesis offered scaling values 1.0 to 3.0 (6.1), larger
    // ones stay usable; the MAR slope spans Guenter et al. 2012's quality range and beyond.
    static const std::vector<ParameterInfo> kParameters{
        {Parameter::Scale, "scale", 0.25, 8.0, false, true},
        {Parameter::RaysPerPoint, "rays-per-point", 1.0, 64.0, true, false},
        {Parameter::K, "k", 1.0, 20.0, true, false},
        {Parameter::Slope, "slope", 0.001, 0.2, false, true},
        {Parameter::Layers, "layers", 2.0, 5.0, true, false},
    };
    return kParameters;
}

const ParameterInfo& infoOf(Parameter p) {
    for (const ParameterInfo& info : parameters()) {
        if (info.parameter == p) {
            return info;
        }
    }
    throw std::invalid_argument("unknown study parameter");
}

std::optional<Parameter> parameterNamed(std::string_view name) {
    for (const ParameterInfo& info : parameters()) {
        if (info.name == name) {
            return info.parameter;
        }
    }
    return std::nullopt;
}

std::string parameterNames() {
    std::string names;
    for (const ParameterInfo& info : parameters()) {
        if (!names.empty()) {
            names += ", ";
        }
        names += info.name;
    }
    return names;
}

RenderChoice withLevel(RenderChoice base, Parameter p, double level) {
    const ParameterInfo& info = infoOf(p);
    const double v = std::clamp(info.integer ? std::round(level) : level, info.min, info.max);
    switch (p) {
    case Parameter::Scale:
        base.scale = v;
        break;
    case Parameter::RaysPerPoint:
        base.raysPerPoint = static_cast<uint32_t>(v);
        break;
    case Parameter::K:
        base.k = static_cast<uint32_t>(v);
        break;
    case Parameter::Slope:
        base.slope = v;
        break;
    case Parameter::Layers:
        base.layers = static_cast<uint32_t>(v);
        break;
    }
    return base;
}

} // namespace gt::study
