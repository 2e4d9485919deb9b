//! The checksum of manifests: FNV-1a over 64 bits. It guards against damaged and
//! mismatched files (a truncated copy, a CSV edited by hand), not against an adversary,
//! and needs no dependency.

/// The checksum of `bytes`, as written in manifests: `fnv1a64:` and 16 hex digits.
///
/// ```
/// assert_eq!(shards::checksum(b""), "fnv1a64:cbf29ce484222325");
/// ```
#[must_use]
pub fn checksum(bytes: &[u8]) -> String {
    format!("fnv1a64:{:016x}", fnv1a64(bytes))
}

pub(crate) fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h: u64, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}
