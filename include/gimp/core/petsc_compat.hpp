// Small compatibility layer over PETSc versions (3.18 is the oldest supported).
#pragma once

#include <petscsys.h>

#if !defined(PETSC_SUCCESS)
#define PETSC_SUCCESS 0 // named in PETSc >= 3.19
#endif
