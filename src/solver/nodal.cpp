#include "gimp/solver/nodal.hpp"

namespace gimp {

Nodal::~Nodal() {
  destroy();
}

void Nodal::destroy() {
  for (Vec *v :
       {&P,     &mass, &vel,  &acc,   &f,    &rhs,  &fext, &bcMask, &mask,  &invMass, &face,
        &vstar, &term, &sumW, &massW, &velW, &accW, &extW, &faceW,  &maskW, &vstarW})
    if (*v) (void)VecDestroy(v);
}

template <int D>
PetscErrorCode Nodal::create(const Grid<D> &grid, bool external, bool cracks, bool xpic) {
  PetscCall(DMCreateGlobalVector(grid.dm, &P));
  PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(P), "momentum"));
  for (Vec *v : {&mass, &vel, &acc, &f, &rhs, &bcMask, &mask, &invMass})
    PetscCall(VecDuplicate(P, v));
  for (Vec *v : {&sumW, &massW, &velW, &accW})
    PetscCall(grid.createWindowVec(v));
  if (cracks) {
    PetscCall(VecDuplicate(P, &face));
    PetscCall(grid.createWindowVec(&faceW));
    PetscCall(grid.createWindowVec(&maskW));
  }
  if (xpic) {
    PetscCall(VecDuplicate(P, &vstar));
    PetscCall(VecDuplicate(P, &term));
    PetscCall(grid.createWindowVec(&vstarW));
  }
  if (external) {
    PetscCall(VecDuplicate(P, &fext));
    PetscCall(grid.createWindowVec(&extW));
  }
  return PETSC_SUCCESS;
}

template PetscErrorCode Nodal::create<2>(const Grid<2> &, bool, bool, bool);
template PetscErrorCode Nodal::create<3>(const Grid<3> &, bool, bool, bool);

} // namespace gimp
