//! sph-mps (filled by its own issue).
