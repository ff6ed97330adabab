//! FMI 2.0 co-simulation FMU for the SHPB specimen. The FMI layer lands with the embedding
//! issue; this crate is a workspace member from the start.
