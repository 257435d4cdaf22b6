//! Benchmark cases as scene builders (filled by the method issues).
