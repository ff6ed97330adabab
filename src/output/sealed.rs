//! Sealed byte envelopes for everything Fractum hands out to be read back later: checkpoint
//! files, the C ABI's state blobs (`fractum_save_state`) and the FMU's serialized states.
//!
//! Layout (little-endian): an 8-byte magic naming what the bytes are, the format version
//! (u32), the payload length (u64), the payload, then a 64-bit FNV-1a checksum of everything
//! before it. Reading checks, in this order, the magic, the length, the checksum and the
//! version, so damaged bytes are refused with a sentence before any of them is decoded. The
//! checksum guards against accidental damage (a truncated copy, a flipped bit: FNV-1a changes
//! with every single-byte change), not against forgery.

/// Bytes before the payload: magic, version, length.
const HEADER: usize = 8 + 4 + 8;
/// Bytes after the payload: the checksum.
const TRAILER: usize = 8;

/// 64-bit FNV-1a of `bytes`.
pub fn checksum(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// `payload` sealed under `magic` and `version`.
pub fn seal(magic: &[u8; 8], version: u32, payload: &[u8]) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(HEADER + payload.len() + TRAILER);
    bytes.extend_from_slice(magic);
    bytes.extend_from_slice(&version.to_le_bytes());
    bytes.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    bytes.extend_from_slice(payload);
    let sum = checksum(&bytes);
    bytes.extend_from_slice(&sum.to_le_bytes());
    bytes
}

/// Why sealed bytes were refused; `Display` completes a sentence that begins with what the
/// bytes are (e.g. "the checkpoint out/x.fcp ...").
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Refused {
    /// The magic is another's: these are not the bytes asked for.
    Foreign,
    /// Shorter or longer than the length they declare.
    Length { declared: u64, found: usize },
    /// The checksum does not match: damaged in storage or transit.
    Checksum,
    /// Written in another format version.
    Version { found: u32, reads: u32 },
}

impl std::fmt::Display for Refused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Refused::Foreign => write!(f, "does not start with the expected Fractum header"),
            Refused::Length { declared, found } => write!(
                f,
                "is truncated or padded: it declares {declared} bytes of content but holds {found}"
            ),
            Refused::Checksum => write!(f, "is damaged: its checksum does not match its content"),
            Refused::Version { found, reads } => write!(
                f,
                "has format version {found}, this Fractum reads version {reads}"
            ),
        }
    }
}

/// The payload of bytes sealed under `magic` and `version`.
pub fn open<'a>(bytes: &'a [u8], magic: &[u8; 8], version: u32) -> Result<&'a [u8], Refused> {
    if bytes.len() < 8 || &bytes[..8] != magic {
        return Err(Refused::Foreign);
    }
    if bytes.len() < HEADER + TRAILER {
        return Err(Refused::Length {
            declared: 0,
            found: bytes.len().saturating_sub(HEADER + TRAILER),
        });
    }
    let word = |at: usize| u64::from_le_bytes(bytes[at..at + 8].try_into().expect("8 bytes"));
    let declared = word(12);
    let found = bytes.len() - HEADER - TRAILER;
    if declared != found as u64 {
        return Err(Refused::Length { declared, found });
    }
    let end = HEADER + found;
    if checksum(&bytes[..end]) != word(end) {
        return Err(Refused::Checksum);
    }
    let found_version = u32::from_le_bytes(bytes[8..12].try_into().expect("4 bytes"));
    if found_version != version {
        return Err(Refused::Version {
            found: found_version,
            reads: version,
        });
    }
    Ok(&bytes[HEADER..end])
}

#[cfg(test)]
mod tests {
    use super::*;

    const MAGIC: &[u8; 8] = b"TESTSEAL";

    #[test]
    fn round_trip() {
        let payload: Vec<u8> = (0..=255).collect();
        let sealed = seal(MAGIC, 7, &payload);
        assert_eq!(sealed.len(), payload.len() + HEADER + TRAILER);
        assert_eq!(open(&sealed, MAGIC, 7), Ok(payload.as_slice()));
        assert_eq!(open(&seal(MAGIC, 7, &[]), MAGIC, 7), Ok(&[][..]));
    }

    /// FNV-1a's published test vectors (Fowler, Noll, Vo).
    #[test]
    fn checksum_is_fnv1a_64() {
        assert_eq!(checksum(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(checksum(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(checksum(b"foobar"), 0x8594_4171_f739_67e8);
    }

    /// Every single-bit flip anywhere is refused, and never as a success.
    #[test]
    fn every_bit_flip_is_refused() {
        let payload: Vec<u8> = (0..64u8).map(|i| i.wrapping_mul(37)).collect();
        let sealed = seal(MAGIC, 3, &payload);
        for byte in 0..sealed.len() {
            for bit in 0..8 {
                let mut damaged = sealed.clone();
                damaged[byte] ^= 1 << bit;
                let got = open(&damaged, MAGIC, 3);
                assert!(got.is_err(), "flip of bit {bit} in byte {byte} accepted");
            }
        }
    }

    #[test]
    fn truncation_other_magic_and_version_are_named() {
        let sealed = seal(MAGIC, 3, b"payload");
        for cut in 0..sealed.len() {
            assert!(
                open(&sealed[..cut], MAGIC, 3).is_err(),
                "cut at {cut} accepted"
            );
        }
        assert_eq!(open(&sealed, b"OTHERMAG", 3), Err(Refused::Foreign));
        assert_eq!(
            open(&sealed, MAGIC, 4),
            Err(Refused::Version { found: 3, reads: 4 })
        );
        let mut longer = sealed.clone();
        longer.push(0);
        assert!(matches!(
            open(&longer, MAGIC, 3),
            Err(Refused::Length {
                declared: 7,
                found: 8
            })
        ));
    }
}
