//! Meshes as they ship (issue 45): zero-area triangles and short OBJ faces
//! accepted and taking part as what they are, and the mesh distance search
//! against the brute force and the exact reference on meshes written to be
//! hard for it (slivers, needles, thin and long parts, far apart scales);
//! mesh files in every format read (issue 46).

mod as_shipped;
mod distance_search;
mod files;
