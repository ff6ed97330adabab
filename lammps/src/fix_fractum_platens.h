/* fix ID group fractum/platens: rigid box faces (platens) with Fractum's wall contact
   (libfractum's fractum_kernel_wall: spheres and poly-ellipsoids, the held Hertz radius, the
   same law as pair fractum/granular), moved at prescribed speeds; their forces come out.

   fix ID group fractum/platens FACE POS [FACE POS ...] [vel FACE SPEED ...] [friction MU]
     FACE     xlo xhi ylo yhi zlo zhi: the plane x = POS (m) etc., facing into the box
     SPEED    m/s along the face's axis, a number or v_name of an equal-style variable (read every
              step: a host drives the faces through it)
     friction Coulomb coefficient against the faces (default: the pair's)

   Global vector (18): 1-6 the force of the grains on each face along its axis (N; xlo, xhi,
   ylo, yhi, zlo, zhi), 7-12 the faces' positions (m), 13-18 their contact counts.
   Per-face contact history lives in d2_fr_walls (42 columns) when friction or non-spherical
   grains need it. */
#ifndef FRACTUM_FIX_PLATENS_H
#define FRACTUM_FIX_PLATENS_H

#include "fix.h"
#include "fractum_atoms.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixFractumPlatens : public Fix {
 public:
  FixFractumPlatens(class LAMMPS *, int, char **);
  int setmask() override;
  void init() override;
  void setup(int) override;
  void initial_integrate(int) override;
  void post_force(int) override;
  double compute_vector(int) override;
  void write_restart(FILE *) override;
  void restart(char *) override;

  static const int FACES = 6;
  bool active[FACES] = {false, false, false, false, false, false};
  double point[FACES][3] = {};
  double normal[FACES][3] = {};
  double velocity[FACES][3] = {};
  double speed[FACES] = {};
  std::string speed_var[FACES];
  double wall_friction = -1.0;

 private:
  class FractumSums *sums = nullptr;
  FractumContactLaw law{};
  int shapes = 0;    // bodies other than spheres take part (the pair's)
  double poisson = 0.0;    // the pair's (the contact tensile stress of a face's contact)
  double local[2 * FACES] = {};    // force along the axis, contacts (this rank)
  double global[2 * FACES] = {};
  bigint reduced_at = -1;
  // The owned atoms of the group that may touch a face before the list is built again, in
  // index order (`near_atoms`), and the faces' positions and the owned count when it was.
  std::vector<int> near;
  double near_point[FACES][3] = {};
  int near_nlocal = -1;
  void speeds();
  bool near_stale() const;
  void near_atoms(double **walls);
};

}    // namespace LAMMPS_NS

#endif
