#pragma once
// The landform scenes (issue 22): embankment, terraces, foot, ridge, badlands; built-in
// scenes like the others (scene.h), kept apart because each is a landform of its own.
#include <random>
#include <string>
#include <vector>

#include "sim/scene.h"

namespace ts::sim {

const std::vector<std::string>& LandformSceneNames();

// Fills the scene's lattice for a landform; false for a name that is not one. rng is the
// scene's generator (seeded from the seed), drawn from for the landform's layout.
bool FillLandformScene(const std::string& name, uint64_t seed, std::mt19937_64& rng, Scene* scene);

}  // namespace ts::sim
