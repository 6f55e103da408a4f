#pragma once
// A drawn stone as a solver body, at either fidelity: the rigid clump of its template, or the
// ball of equal volume (and so equal mass) at the same centre. Both come from the same draw, so
// models compare pairwise on identical stones.
#include "dem/simulation.hpp"
#include "fidelity/clump_template.hpp"
#include "fidelity/grading.hpp"
#include "fidelity/policy.hpp"

namespace mfdem::fidelity {

dem::ClumpSpec stone_as_clump(const ClumpTemplate& shape, const StoneDraw& draw, double density,
                              int material, const dem::Vec3& centre);
dem::SphereSpec stone_as_ball(const ClumpTemplate& shape, const StoneDraw& draw, int material,
                              const dem::Vec3& centre);

// Largest distance of the template's surface (pebbles) from its centre of mass, units of d.
double template_reach(const ClumpTemplate& shape);

}  // namespace mfdem::fidelity
