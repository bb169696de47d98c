//! The resistance with lubrication (Eq. 19): its assembly and positive definiteness,
//! its accuracy against exact results at a wall, a free surface and between two spheres,
//! the window that switches the pair correction off, the sphere-wall tables, and a side
//! wall as the wall turned.

mod free_surface;
mod pair_window;
mod resistance;
mod side_wall;
mod vs_exact;
mod wall_tables;
