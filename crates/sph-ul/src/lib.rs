//! sph-ul (filled by its own issue).
