/* The disk (2D) and ball (3D) of docs/design.md §7 dropped on a plane: one driver,
 * used by examples/disk2d.c and examples/ball3d.c. */
#ifndef ND_DROP_SCENE_H
#define ND_DROP_SCENE_H
#include "nitschedyn.h"

#ifdef __cplusplus
extern "C" {
#endif
/* The problem of the scene on a Gmsh mesh (region 1 = contact boundary). */
int drop_scene_create(int dim, const char *mesh, int degree, int scheme, const double *params, double Theta,
                      double gamma0, double tau, int solver, nd_problem *out);
/* The command-line driver (--help). */
int drop_scene_main(int argc, char **argv, int dim);
#ifdef __cplusplus
}
#endif
#endif
