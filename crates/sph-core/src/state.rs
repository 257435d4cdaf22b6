//! Solver state for checkpoints: a small, exact binary encoding ([`StateWriter`],
//! [`StateReader`]) that [`crate::Solver::save_state`] and [`crate::Solver::restore_state`] use.
//!
//! Every value is written little-endian with its full bits (floats via `to_bits`), so a state
//! read back is bit-identical to the one written. Each array carries its name and length: a
//! reader that expects another name or length fails with [`Error::Checkpoint`] naming both,
//! rather than misreading the bytes (a checkpoint of another case, parameters or method). The
//! neighbour list and everything derived from the reference configuration are not written:
//! a solver rebuilds them from the scene, then reads its evolving state back.

use crate::dim::Dim;
use crate::error::Error;

/// Appends named values to a byte buffer.
#[derive(Debug, Default)]
pub struct StateWriter {
    buf: Vec<u8>,
}

impl StateWriter {
    /// An empty buffer.
    pub fn new() -> Self {
        Self::default()
    }

    /// The bytes written.
    pub fn into_bytes(self) -> Vec<u8> {
        self.buf
    }

    /// One unsigned integer.
    pub fn u64(&mut self, x: u64) {
        self.buf.extend_from_slice(&x.to_le_bytes());
    }

    /// One float, all its bits.
    pub fn f64(&mut self, x: f64) {
        self.u64(x.to_bits());
    }

    /// A length-prefixed byte string.
    pub fn bytes(&mut self, b: &[u8]) {
        self.u64(b.len() as u64);
        self.buf.extend_from_slice(b);
    }

    /// A length-prefixed UTF-8 string.
    pub fn str(&mut self, s: &str) {
        self.bytes(s.as_bytes());
    }

    /// A section name and its count of entries (checked by [`StateReader::begin`]).
    pub fn begin(&mut self, name: &str, len: usize) {
        self.str(name);
        self.u64(len as u64);
    }

    /// Named scalars (a fixed group of values, e.g. `time`, `steps`).
    pub fn f64s(&mut self, name: &str, v: &[f64]) {
        self.begin(name, v.len());
        v.iter().for_each(|&x| self.f64(x));
    }

    /// Named unsigned integers.
    pub fn u64s(&mut self, name: &str, v: &[u64]) {
        self.begin(name, v.len());
        v.iter().for_each(|&x| self.u64(x));
    }

    /// Named vectors (`D::D` components each).
    pub fn vectors<D: Dim>(&mut self, name: &str, v: &[D::Vector]) {
        self.begin(name, v.len());
        for &x in v {
            (0..D::D).for_each(|k| self.f64(D::component(x, k)));
        }
    }

    /// Named matrices (`D::D²` entries each, row by row).
    pub fn matrices<D: Dim>(&mut self, name: &str, m: &[D::Matrix]) {
        self.begin(name, m.len());
        for &x in m {
            for r in 0..D::D {
                (0..D::D).for_each(|c| self.f64(D::matrix_get(x, r, c)));
            }
        }
    }
}

/// Reads back what a [`StateWriter`] wrote, checking names and lengths.
#[derive(Debug)]
pub struct StateReader<'a> {
    buf: &'a [u8],
    pos: usize,
}

fn bad(msg: String) -> Error {
    Error::Checkpoint(msg)
}

impl<'a> StateReader<'a> {
    /// A reader over `buf`.
    pub fn new(buf: &'a [u8]) -> Self {
        Self { buf, pos: 0 }
    }

    /// Whether every byte has been read.
    pub fn is_at_end(&self) -> bool {
        self.pos == self.buf.len()
    }

    fn take(&mut self, n: usize) -> Result<&'a [u8], Error> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.buf.len());
        let end = end.ok_or_else(|| {
            bad(format!(
                "the state ends after {} bytes, {n} more were expected",
                self.buf.len()
            ))
        })?;
        let s = &self.buf[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    /// One unsigned integer.
    pub fn u64(&mut self) -> Result<u64, Error> {
        let b = self.take(8)?;
        Ok(u64::from_le_bytes(b.try_into().expect("8 bytes")))
    }

    /// One float.
    pub fn f64(&mut self) -> Result<f64, Error> {
        self.u64().map(f64::from_bits)
    }

    /// A length-prefixed byte string.
    pub fn bytes(&mut self) -> Result<&'a [u8], Error> {
        let n = self.u64()?;
        let n = usize::try_from(n).map_err(|_| bad(format!("a length of {n} bytes")))?;
        self.take(n)
    }

    /// A length-prefixed UTF-8 string.
    pub fn str(&mut self) -> Result<&'a str, Error> {
        std::str::from_utf8(self.bytes()?).map_err(|e| bad(format!("a name is not UTF-8: {e}")))
    }

    /// Reads a section header: it must be `name`; returns its count of entries, which must be
    /// `expected` if given.
    pub fn begin(&mut self, name: &str, expected: Option<usize>) -> Result<usize, Error> {
        let found = self.str()?;
        if found != name {
            return Err(bad(format!(
                "expected the section `{name}`, found `{found}`"
            )));
        }
        let n = self.u64()?;
        let n = usize::try_from(n).map_err(|_| bad(format!("`{name}` has {n} entries")))?;
        if let Some(e) = expected.filter(|&e| e != n) {
            return Err(bad(format!(
                "`{name}` has {n} entries where this run has {e} (a checkpoint of another case, \
                 parameters or method?)"
            )));
        }
        // Every entry takes at least 8 bytes: refuse a count the rest cannot hold before
        // allocating for it.
        if n > (self.buf.len() - self.pos) / 8 {
            return Err(bad(format!(
                "`{name}` claims {n} entries, more than the file holds"
            )));
        }
        Ok(n)
    }

    /// Named scalars; `expected` entries if given.
    pub fn f64s(&mut self, name: &str, expected: Option<usize>) -> Result<Vec<f64>, Error> {
        let n = self.begin(name, expected)?;
        (0..n).map(|_| self.f64()).collect()
    }

    /// Named unsigned integers; `expected` entries if given.
    pub fn u64s(&mut self, name: &str, expected: Option<usize>) -> Result<Vec<u64>, Error> {
        let n = self.begin(name, expected)?;
        (0..n).map(|_| self.u64()).collect()
    }

    /// Named vectors; `expected` entries if given.
    pub fn vectors<D: Dim>(
        &mut self,
        name: &str,
        expected: Option<usize>,
    ) -> Result<Vec<D::Vector>, Error> {
        let n = self.begin(name, expected)?;
        (0..n)
            .map(|_| {
                let mut c = [0.0; 3];
                for x in c.iter_mut().take(D::D) {
                    *x = self.f64()?;
                }
                Ok(D::vector(c))
            })
            .collect()
    }

    /// Named matrices; `expected` entries if given.
    pub fn matrices<D: Dim>(
        &mut self,
        name: &str,
        expected: Option<usize>,
    ) -> Result<Vec<D::Matrix>, Error> {
        let n = self.begin(name, expected)?;
        (0..n)
            .map(|_| {
                let mut e = [[0.0; 3]; 3];
                for row in e.iter_mut().take(D::D) {
                    for x in row.iter_mut().take(D::D) {
                        *x = self.f64()?;
                    }
                }
                Ok(D::matrix_from_fn(|r, c| e[r][c]))
            })
            .collect()
    }

    /// Fixed scalars: exactly `N` values named `name`.
    pub fn scalars<const N: usize>(&mut self, name: &str) -> Result<[f64; N], Error> {
        let v = self.f64s(name, Some(N))?;
        Ok(v.try_into().expect("N values"))
    }
}

/// Writes the probes' records (times, positions, velocities; the targets come from the scene).
pub fn save_probes<D: Dim>(out: &mut StateWriter, probes: &[crate::Probe<D>]) {
    out.begin("probes", probes.len());
    for p in probes {
        out.str(&p.name);
        out.f64s("times", &p.times);
        out.vectors::<D>("positions", &p.positions);
        out.vectors::<D>("velocities", &p.velocities);
    }
}

/// Reads back [`save_probes`] into the scene's probes (same names, same order).
pub fn restore_probes<D: Dim>(
    input: &mut StateReader<'_>,
    probes: &mut [crate::Probe<D>],
) -> Result<(), Error> {
    input.begin("probes", Some(probes.len()))?;
    for p in probes {
        let name = input.str()?;
        if name != p.name {
            return Err(bad(format!(
                "probe `{name}` where this run has `{}`",
                p.name
            )));
        }
        p.times = input.f64s("times", None)?;
        p.positions = input.vectors::<D>("positions", Some(p.times.len()))?;
        p.velocities = input.vectors::<D>("velocities", Some(p.times.len()))?;
    }
    Ok(())
}

/// Writes recorded series (their sample times and columns).
pub fn save_series(out: &mut StateWriter, series: &[crate::Series]) {
    out.begin("series", series.len());
    for s in series {
        out.str(&s.name);
        out.f64s("time", &s.time);
        out.begin("columns", s.values.len());
        for v in &s.values {
            out.f64s("values", v);
        }
    }
}

/// Reads back [`save_series`] into series of the same names and columns.
pub fn restore_series(
    input: &mut StateReader<'_>,
    series: &mut [crate::Series],
) -> Result<(), Error> {
    input.begin("series", Some(series.len()))?;
    for s in series {
        let name = input.str()?;
        if name != s.name {
            return Err(bad(format!(
                "series `{name}` where this run has `{}`",
                s.name
            )));
        }
        s.time = input.f64s("time", None)?;
        input.begin("columns", Some(s.values.len()))?;
        for v in s.values.iter_mut() {
            *v = input.f64s("values", Some(s.time.len()))?;
        }
    }
    Ok(())
}

/// The FNV-1a 64-bit hash of `bytes`: the checkpoint file's checksum (detects truncation and
/// corruption; not a cryptographic hash).
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{D2, D3};
    use glam::{DMat3, DVec2, DVec3};

    #[test]
    fn values_round_trip_bit_for_bit() {
        let mut w = StateWriter::new();
        let v2 = vec![DVec2::new(0.1, -3e-300), DVec2::new(f64::NAN, 7.0)];
        let m3 = vec![DMat3::from_cols_array(&[
            1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 0.1,
        ])];
        w.vectors::<D2>("x", &v2);
        w.matrices::<D3>("f", &m3);
        w.f64s("t", &[0.3, -0.0]);
        let bytes = w.into_bytes();
        let mut r = StateReader::new(&bytes);
        let x = r.vectors::<D2>("x", Some(2)).unwrap();
        assert_eq!(x[0], v2[0]);
        assert!(x[1].x.is_nan() && x[1].y == 7.0);
        assert_eq!(r.matrices::<D3>("f", None).unwrap(), m3);
        let [a, b] = r.scalars::<2>("t").unwrap();
        assert_eq!(
            (a.to_bits(), b.to_bits()),
            (0.3f64.to_bits(), (-0.0f64).to_bits())
        );
        assert!(r.is_at_end());
    }

    #[test]
    fn wrong_name_length_or_truncation_is_an_error() {
        let mut w = StateWriter::new();
        w.vectors::<D3>("positions", &[DVec3::ONE; 4]);
        let bytes = w.into_bytes();
        let e = StateReader::new(&bytes).vectors::<D3>("velocities", None);
        assert!(e.unwrap_err().to_string().contains("`velocities`"));
        let e = StateReader::new(&bytes).vectors::<D3>("positions", Some(5));
        assert!(e
            .unwrap_err()
            .to_string()
            .contains("4 entries where this run has 5"));
        let e = StateReader::new(&bytes[..bytes.len() - 1]).vectors::<D3>("positions", None);
        assert!(e.unwrap_err().to_string().contains("ends after"));
    }

    #[test]
    fn checksum_sees_a_flipped_bit() {
        let a = fnv1a64(b"checkpoint");
        assert_ne!(a, fnv1a64(b"checkpoinu"));
        assert_eq!(a, fnv1a64(b"checkpoint"));
    }
}
