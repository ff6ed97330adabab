/* fix ID group fractum/platens: rigid box faces (platens) with Fractum's wall contact
   (libfractum's fractum_kernel_wall: spheres and poly-ellipsoids, the held Hertz radius, the
   same law as pair fractum/granular), moved at prescribed speeds; their forces come out.

   fix ID group fractum/platens FACE POS [FACE POS ...] [vel FACE SPEED ...] [friction MU]
       [sleeve CX CY R [sleeve_friction MU]]
     FACE     xlo xhi ylo yhi zlo zhi: the plane x = POS (m) etc., facing into the box
     SPEED    m/s along the face's axis, a number or v_name of an equal-style variable (read every
              step: a host drives the faces through it)
     friction Coulomb coefficient against the faces (default: the pair's)
     sleeve   a fixed rigid circular cylinder of inner radius R (m), its axis along z through
              (CX, CY) (m), in place of the side faces (libfractum's fractum_kernel_sleeve, as
              Fractum's walls.sleeve); it needs zlo and zhi, which close it
     sleeve_friction  Coulomb coefficient against the sleeve (default: the faces')

   Global vector (31): 1-6 the force of the grains on each face along its axis (N; xlo, xhi,
   ylo, yhi, zlo, zhi), 7-12 the faces' positions (m), 13-18 their contact counts; with a sleeve
   19 the sum of its contacts' normal (radial) forces (N, compression positive), 20 the force
   along z the grains exert on it by friction (N), 21 its contact count, 22-31 the radial forces
   by ten equal axial slices of the span from zlo up (N; 0 without a sleeve).
   Per-face contact history lives in d2_fr_walls (42 columns, 49 with a sleeve) when friction or
   non-spherical grains need it. */
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
  static const int SLICES = 10;
  bool sleeve = false;
  double sleeve_centre[3] = {};
  double sleeve_radius = 0.0;
  double sleeve_friction = -1.0;

 private:
  class FractumSums *sums = nullptr;
  FractumContactLaw law{};
  int shapes = 0;    // bodies other than spheres take part (the pair's)
  double poisson = 0.0;    // the pair's (the contact tensile stress of a face's contact)
  FractumContactLaw sleeve_law{};
  // Force along the axis and contacts of each face, then the sleeve's radial force, axial
  // force, contacts and radial force by slice (this rank, and summed over the ranks).
  static const int SUMS = 2 * FACES + 3 + SLICES;
  double local[SUMS] = {};
  double global[SUMS] = {};
  bigint reduced_at = -1;
  // The owned atoms of the group that may touch a face before the list is built again, in
  // index order (`near_atoms`), and the faces' positions and the owned count when it was.
  std::vector<int> near;
  double near_point[FACES][3] = {};
  int near_nlocal = -1;
  void speeds();
  void sleeve_contact(int i, double **walls, const FractumBody &b, bool frequency_due,
                      bool keep_memory, int update_history, double **grain);
  double clearance(int i, int w) const;
  bool reaches(double **walls, int i, int w) const;
  bool near_stale() const;
  void near_atoms(double **walls);
};

}    // namespace LAMMPS_NS

#endif
