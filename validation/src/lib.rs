//! Validation runs (filled by the method issues).
