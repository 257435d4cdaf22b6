//! sph-tl (filled by its own issue).
