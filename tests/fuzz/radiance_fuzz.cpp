// Fuzz target: the Radiance (.hdr) reader. Contract (radiance_hdr.hpp): malformed, truncated or
// unsupported bytes throw gt::LoadError starting with the name; a decoded picture has exactly
// width x height x 3 finite, non-negative values.
#include <cmath>
#include <span>
#include <string>

#include "fuzz_input.hpp"

#include "core/error.hpp"
#include "scene/radiance_hdr.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using gt::fuzz::finding;
    const std::string name = "sky.hdr";
    try {
        const gt::scene::RgbImage img = gt::scene::decodeRadianceHdr({data, size}, name);
        if (img.width < 1 || img.height < 1 ||
            img.rgb.size() != static_cast<std::size_t>(img.width) * img.height * 3) {
            finding("a picture's size and its values disagree");
        }
        for (const float v : img.rgb) {
            if (!std::isfinite(v) || v < 0.0f) finding("a value that is negative or not finite");
        }
    } catch (const gt::LoadError& e) {
        if (std::string(e.what()).rfind(name + ": ", 0) != 0) {
            finding(std::string("error does not start with the name: ") + e.what());
        }
    } catch (const std::exception& e) {
        finding(std::string("not a LoadError: ") + e.what());
    }
    return 0;
}
