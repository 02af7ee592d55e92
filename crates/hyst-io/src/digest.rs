//! The size and FNV-1a 64-bit hash of an input, taken while it is read: a pipe or a FIFO can
//! be read only once, so a second read for the hash would record the hash of nothing (or wait
//! for a writer that never comes).

use std::cell::Cell;
use std::io::{self, Read};
use std::rc::Rc;

/// How many bytes an input had and their FNV-1a 64-bit hash (the model file's provenance).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Digest {
    /// Bytes read.
    pub bytes: u64,
    /// FNV-1a 64-bit hash of those bytes.
    pub fnv1a64: u64,
}

impl Default for Digest {
    fn default() -> Self {
        Self {
            bytes: 0,
            fnv1a64: 0xcbf2_9ce4_8422_2325,
        }
    }
}

impl Digest {
    /// The digest after `data` more bytes.
    #[must_use]
    pub fn update(mut self, data: &[u8]) -> Self {
        for b in data {
            self.fnv1a64 ^= u64::from(*b);
            self.fnv1a64 = self.fnv1a64.wrapping_mul(0x0000_0100_0000_01b3);
        }
        self.bytes += data.len() as u64;
        self
    }
}

/// A reader that updates a shared [`Digest`] with every byte it passes on.
pub(crate) struct Hashing<R> {
    inner: R,
    digest: Rc<Cell<Digest>>,
}

impl<R> Hashing<R> {
    /// `inner`, and the handle to its digest.
    pub(crate) fn new(inner: R) -> (Self, Rc<Cell<Digest>>) {
        let digest = Rc::new(Cell::new(Digest::default()));
        (
            Self {
                inner,
                digest: Rc::clone(&digest),
            },
            digest,
        )
    }
}

impl<R: Read> Read for Hashing<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        let read = buf.get(..n).unwrap_or_default();
        self.digest.set(self.digest.get().update(read));
        Ok(n)
    }
}

/// A reader that tells `on_read` how many bytes it has read so far after every read (a
/// progress display of a long file: `hyst fit` and `hyst run` on a terminal).
pub struct CountingReader<R> {
    inner: R,
    read: u64,
    on_read: Box<dyn FnMut(u64)>,
}

impl<R> CountingReader<R> {
    /// `inner`, counted for `on_read`.
    pub fn new(inner: R, on_read: Box<dyn FnMut(u64)>) -> Self {
        Self {
            inner,
            read: 0,
            on_read,
        }
    }
}

impl<R: Read> Read for CountingReader<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.read = self.read.saturating_add(n as u64);
        (self.on_read)(self.read);
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_digest_is_fnv1a64_of_what_passed() {
        // FNV-1a 64 of "a" (the reference value of the algorithm's authors).
        assert_eq!(
            Digest::default().update(b"a").fnv1a64,
            0xaf63_dc4c_8601_ec8c
        );
        let (mut reader, digest) = Hashing::new(&b"x,y\n1,2\n"[..]);
        let mut all = Vec::new();
        reader.read_to_end(&mut all).ok();
        assert_eq!(digest.get(), Digest::default().update(b"x,y\n1,2\n"));
        assert_eq!(digest.get().bytes, 8);
    }
}
