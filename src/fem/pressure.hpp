#pragma once
// Cavity pressure as a follower load: on every chamber face (normal n out of the solid, into
// the cavity, area a, current geometry) the gas pushes the wall with −p a n, split equally
// over the face's three nodes. Recomputed from the current positions every step (its
// non-symmetric load stiffness is left out of the system matrix, as in SOFA).
#include <vector>

#include <Eigen/Core>

#include "fem/mesh.hpp"

namespace codesign::fem {

// Adds the pressure forces [µN] to f (3N). pressures_Pa[c] for chamber c (missing → 0).
void add_pressure_forces(const TetMesh& mesh, const Eigen::VectorXd& x,
                         const std::vector<double>& pressures_Pa, Eigen::VectorXd& f);

}  // namespace codesign::fem
