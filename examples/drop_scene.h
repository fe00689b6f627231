/* The disk (2D) and ball (3D) of DESIGN §7 dropped on a plane: one driver,
 * used by examples/disk2d.c and examples/ball3d.c. */
#ifndef ND_DROP_SCENE_H
#define ND_DROP_SCENE_H
int drop_scene_main(int argc, char **argv, int dim);
#endif
