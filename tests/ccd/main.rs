//! Continuous collision detection: the linear-vertex queries against
//! analytic times of impact, the contact contract, and the mesh CCD never
//! late against a brute-force scan.

mod ccd_analytic;
mod closest_approach;
mod collection;
mod contact_contract;
mod large_floor_contact_time;
mod mesh_ccd_scan;
mod pivot;
