// Resilient layers of the track: under-sleeper pads (between each sleeper
// and the ballast under it) and under-ballast mats (between the ballast and
// the ground or soil). docs/model.md, "Resilient layers", derives the model:
// each layer is a spring k = k'' A with a viscous damper c = eta k / omega_ref
// (the hysteretic loss factor eta, exact at omega_ref), and a layer adds one
// degree of freedom per sleeper under it or over it, which carries the
// ballast's mass m_b (all of it with one layer, half at each interface with
// both).
#pragma once

#include "scene.hpp"
#include "track_model.hpp"

namespace railcosim {

class SceneReader;

// The masses above each layer, per sleeper (the closed form's m and the
// default reference frequency): a pad carries the sleeper and the rail over
// one sleeper bay, a mat those and the ballast.
double mass_above_pad(const Scene& scene);
double mass_above_mat(const Scene& scene);

// The closed form of the track's resonance each layer makes, Hz: the
// masses above the layer on its spring (f0 = sqrt(k / m) / 2 pi; a pad in
// series with the ballast under it, a mat alone: the ballast above it moves
// with the masses); the default reference frequency of the layer's damper.
double pad_resonance(const Scene& scene);
double mat_resonance(const Scene& scene);

// The layer as the model's spring and damper: k = k'' A, c = eta k / (2 pi f_ref).
SpringDamper layer_spring(const ResilientLayer& layer);

// The mass of each interface DOF: m_b with one layer, m_b / 2 with two.
double interface_mass(const Scene& scene);

// Reads [under_sleeper_pads], [under_ballast_mats] and [ballast] mass
// (common/scene.cpp calls it after [ballast]); the default reference
// frequency is the layer's resonance on the masses above it.
void read_layers(SceneReader& reader, Scene& scene);

// The layers' values against their ranges (Scene::validate, for a scene from
// the wire as from a file): throws SceneError naming the key.
void check_layers(const Scene& scene);

}  // namespace railcosim
