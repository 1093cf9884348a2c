//! A small binary format for FMU states: little-endian numbers with bounds-checked reads, so
//! that a truncated or corrupted buffer is an error, never a crash. Floats are stored bit for
//! bit, so a restored state continues exactly as the saved one.

/// Appends values to a byte buffer.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StateWriter {
    buf: Vec<u8>,
}

impl StateWriter {
    /// An empty writer.
    pub fn new() -> Self {
        Self::default()
    }
    /// The bytes written so far.
    pub fn into_bytes(self) -> Vec<u8> {
        self.buf
    }
    /// Bytes written so far.
    pub fn bytes(&self) -> &[u8] {
        &self.buf
    }
    /// A u64.
    pub fn u64(&mut self, v: u64) {
        self.buf.extend_from_slice(&v.to_le_bytes());
    }
    /// A f64 (bit pattern).
    pub fn f64(&mut self, v: f64) {
        self.u64(v.to_bits());
    }
    /// A bool as one byte.
    pub fn bool(&mut self, v: bool) {
        self.buf.push(u8::from(v));
    }
    /// A slice of f64 with its length.
    pub fn f64s(&mut self, v: &[f64]) {
        self.u64(v.len() as u64);
        for x in v {
            self.f64(*x);
        }
    }
    /// A string with its length.
    pub fn str(&mut self, s: &str) {
        self.u64(s.len() as u64);
        self.buf.extend_from_slice(s.as_bytes());
    }
}

/// Reads values written by [`StateWriter`], failing cleanly at the end of the data.
#[derive(Clone, Debug)]
pub struct StateReader<'a> {
    data: &'a [u8],
    pos: usize,
}

/// A buffer that does not hold what was expected.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("invalid FMU state data: {0}")]
pub struct SnapshotError(pub String);

impl<'a> StateReader<'a> {
    /// A reader over `data`.
    pub fn new(data: &'a [u8]) -> Self {
        Self { data, pos: 0 }
    }
    fn take(&mut self, n: usize) -> Result<&'a [u8], SnapshotError> {
        let end = self
            .pos
            .checked_add(n)
            .filter(|&e| e <= self.data.len())
            .ok_or_else(|| SnapshotError(format!("truncated at byte {}", self.pos)))?;
        let s = &self.data[self.pos..end];
        self.pos = end;
        Ok(s)
    }
    /// A u64.
    pub fn u64(&mut self) -> Result<u64, SnapshotError> {
        Ok(u64::from_le_bytes(
            self.take(8)?.try_into().expect("8 bytes"),
        ))
    }
    /// A f64.
    pub fn f64(&mut self) -> Result<f64, SnapshotError> {
        Ok(f64::from_bits(self.u64()?))
    }
    /// A bool.
    pub fn bool(&mut self) -> Result<bool, SnapshotError> {
        match self.take(1)?[0] {
            0 => Ok(false),
            1 => Ok(true),
            b => Err(SnapshotError(format!("invalid boolean byte {b}"))),
        }
    }
    /// A vector of f64 whose length must be `expect` (if given).
    pub fn f64s(&mut self, expect: Option<usize>) -> Result<Vec<f64>, SnapshotError> {
        let n = self.len()?;
        if let Some(e) = expect
            && n != e
        {
            return Err(SnapshotError(format!("expected {e} values, found {n}")));
        }
        (0..n).map(|_| self.f64()).collect()
    }
    /// Reads exactly `out.len()` f64 into `out` (length-prefixed).
    pub fn f64s_into(&mut self, out: &mut [f64]) -> Result<(), SnapshotError> {
        let n = self.len()?;
        if n != out.len() {
            return Err(SnapshotError(format!(
                "expected {} values, found {n}",
                out.len()
            )));
        }
        for x in out.iter_mut() {
            *x = self.f64()?;
        }
        Ok(())
    }
    /// A string.
    pub fn str(&mut self) -> Result<String, SnapshotError> {
        let n = self.len()?;
        String::from_utf8(self.take(n)?.to_vec())
            .map_err(|_| SnapshotError("string is not UTF-8".into()))
    }
    /// A length prefix, checked against the remaining data (8 bytes per element at least 1).
    fn len(&mut self) -> Result<usize, SnapshotError> {
        let n = self.u64()?;
        let remaining = (self.data.len() - self.pos) as u64;
        if n > remaining {
            return Err(SnapshotError(format!(
                "length {n} exceeds the remaining {remaining} bytes"
            )));
        }
        Ok(n as usize)
    }
    /// Whether all data was consumed.
    pub fn finished(&self) -> bool {
        self.pos == self.data.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_truncation() {
        let mut w = StateWriter::new();
        w.f64(-0.0);
        w.f64(f64::NAN);
        w.bool(true);
        w.f64s(&[1.0, 2.5]);
        w.str("guid");
        let b = w.into_bytes();
        let mut r = StateReader::new(&b);
        assert_eq!(r.f64().unwrap().to_bits(), (-0.0f64).to_bits());
        assert!(r.f64().unwrap().is_nan());
        assert!(r.bool().unwrap());
        assert_eq!(r.f64s(Some(2)).unwrap(), vec![1.0, 2.5]);
        assert_eq!(r.str().unwrap(), "guid");
        assert!(r.finished());
        for cut in 0..b.len() {
            let mut r = StateReader::new(&b[..cut]);
            let ok = r
                .f64()
                .and_then(|_| r.f64())
                .and_then(|_| r.bool())
                .and_then(|_| r.f64s(None))
                .and_then(|_| r.str());
            assert!(ok.is_err(), "cut at {cut} must fail");
        }
    }
}
