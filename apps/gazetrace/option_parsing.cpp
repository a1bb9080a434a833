#include "option_parsing.hpp"

#include <cmath>
#include <exception>

#include "core/error.hpp"

namespace gt::app {

render::Interpolation parseInterpolation(const std::string& name) {
    if (name == "nn") return render::Interpolation::Nearest;
    if (name == "msm") return render::Interpolation::Shepard;
    if (name == "rbf") return render::Interpolation::Rbf;
    throw ArgumentError("--interp: '" + name + "' is not available (known: nn, msm, rbf)");
}

render::RbfKernel parseKernel(const std::string& name) {
    if (name == "multiquadric") return render::RbfKernel::Multiquadric;
    if (name == "gaussian") return render::RbfKernel::Gaussian;
    throw ArgumentError("--kernel: '" + name +
                        "' is not available (known: multiquadric, gaussian)");
}

render::KnnIndex parseKnnIndex(const std::string& name) {
    if (name == "lists") return render::KnnIndex::NeighbourLists;
    if (name == "table") return render::KnnIndex::PixelTable;
    throw ArgumentError("--knn: '" + name + "' is not available (known: lists, table)");
}

render::Interpolation parseView(const std::string& name) {
    if (name == "points") return render::Interpolation::ViewPoints;
    if (name == "cells") return render::Interpolation::ViewCells;
    if (name == "eccentricity") return render::Interpolation::ViewSpacing;
    throw ArgumentError("--view: '" + name +
                        "' is not available (known: points, cells, eccentricity)");
}

render::Reconstruction parseReconstruction(const std::string& name) {
    if (name == "thesis") return render::Reconstruction::Thesis;
    if (name == "gazetrace") return render::Reconstruction::Gazetrace;
    throw ArgumentError("--reconstruction: expected gazetrace or thesis, got '" + name + "'");
}

double parseSlope(const std::string& text) {
    if (text == "A" || text == "a") {
        return foveation::kSlopeA;
    }
    if (text == "B" || text == "b") {
        return foveation::kSlopeB;
    }
    std::size_t used = 0;
    double v = 0.0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || text.empty() || !(v > 0.0) || !std::isfinite(v)) {
        throw ArgumentError("--slope: '" + text + "' (A, B or a positive MAR slope such as 0.03)");
    }
    return v;
}

render::PresentMode parsePresentMode(const std::string& name) {
    if (name == "fifo") return render::PresentMode::Fifo;
    if (name == "mailbox") return render::PresentMode::Mailbox;
    if (name == "immediate") return render::PresentMode::Immediate;
    throw ArgumentError("--present: unknown mode '" + name + "' (known: fifo, mailbox, immediate)");
}

render::HmdModel parseHmd(const std::string& name) {
    if (name == "fove") return render::HmdModel::Fove;
    if (name == "vive") return render::HmdModel::Vive;
    if (name == "rift-cv1") return render::HmdModel::RiftCv1;
    throw ArgumentError("--hmd: unknown profile '" + name + "' (known: fove, vive, rift-cv1)");
}

display::HmdProfile hmdProfile(const std::string& name) {
    return display::hmdProfile(parseHmd(name));
}

std::vector<std::string> hmdProfileNames() {
    return {"fove", "vive", "rift-cv1"};
}

render::DisplayModel parseDisplay(const std::string& name) {
    if (name == "fove") return render::DisplayModel::Fove;
    if (name == "vive") return render::DisplayModel::Vive;
    if (name == "desktop") return render::DisplayModel::Desktop;
    throw ArgumentError("unknown display profile '" + name + "' (known: fove, vive, desktop)");
}

foveation::DisplayProfile displayProfile(const std::string& name) {
    return foveation::displayProfile(parseDisplay(name));
}

std::vector<std::string> displayProfileNames() {
    return {"fove", "vive", "desktop"};
}

} // namespace gt::app
