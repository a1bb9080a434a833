#pragma once
// Procedural scenes shipped in the binary, so `make run` and the tests need no files.
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace gt::scene {

// "builtin:market": a market hall built around the cases the thesis's user study found hardest
// (thesis, section 6.3): dark pillars against bright walls, bright ceiling lights, shadows cast
// on a lit floor, a tree with many small leaves, and human-sized figures. Plus a mirror sphere
// and glass shopfronts for the metallic bounce, and an open far end showing the sky.
[[nodiscard]] Scene makeMarket();
// "builtin:cornell": the Cornell box with a ceiling light, a diffuse and a mirror block.
[[nodiscard]] Scene makeCornell();

[[nodiscard]] std::vector<std::string> builtinSceneNames();
// `spec` is "builtin:NAME"; throws LoadError for an unknown name.
[[nodiscard]] Scene makeBuiltin(const std::string& spec);

} // namespace gt::scene
