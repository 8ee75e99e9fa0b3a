//! Inputs identified by content: a result that depends on an input file
//! (`--initial-slip FILE`) records the file's SHA-256 digest in its header,
//! so that `--resume` and `merge` refuse a file replaced meanwhile, whatever
//! its name.

use sha2::{Digest, Sha256};

/// Hex digits of a digest recorded in a header: 64 bits are plenty to tell
/// two inputs apart, and keep the header line readable.
pub const RECORDED_HEX: usize = 16;

/// The SHA-256 digest of `bytes` in lower-case hex (64 digits).
pub fn digest_hex(bytes: &[u8]) -> String {
    let digest = Sha256::digest(bytes);
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

/// The short form recorded in headers and names: the first
/// [`RECORDED_HEX`] hex digits of [`digest_hex`].
pub fn content_id(bytes: &[u8]) -> String {
    let mut d = digest_hex(bytes);
    d.truncate(RECORDED_HEX);
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sha256_of_known_text() {
        // FIPS 180-2, appendix B.1.
        assert_eq!(
            digest_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        assert_eq!(content_id(b"abc"), "ba7816bf8f01cfea");
    }
}
