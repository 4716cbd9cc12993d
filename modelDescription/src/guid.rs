//! The GUID of `modelDescription.xml`, derived from the file's content.
//!
//! `build.rs` (the GUID compiled into the binary) and `cargo xtask fmu` (the
//! GUID written into the packaged `modelDescription.xml`) both take it from
//! [`crate::compile`], which calls [`guid_for_xml`]: one function, one GUID.
//!
//! The GUID is a 128-bit FNV-1a hash of the model description *as written*
//! (with the `@GUID@` placeholder still in it), so every edit of the XML
//! yields a new GUID and identical files always yield the same one. Carriage
//! returns are skipped so a CRLF checkout hashes like an LF one. The hash is
//! stamped as an RFC 9562 version-8 ("custom") UUID and formatted the way
//! FMI tools expect: `{xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx}`.

/// The placeholder that stands for the GUID in the hand-written XML.
pub const GUID_PLACEHOLDER: &str = "@GUID@";

const FNV128_OFFSET_BASIS: u128 = 0x6c62_272e_07bb_0142_62b8_2175_6295_c58d;
const FNV128_PRIME: u128 = 0x0000_0000_0100_0000_0000_0000_0000_013b;

/// 128-bit FNV-1a over `bytes`.
pub fn fnv1a_128(bytes: impl IntoIterator<Item = u8>) -> u128 {
    bytes.into_iter().fold(FNV128_OFFSET_BASIS, |h, b| {
        (h ^ u128::from(b)).wrapping_mul(FNV128_PRIME)
    })
}

/// Format 128 bits as a version-8 UUID in braces, lower-case hex.
pub fn format_guid(hash: u128) -> String {
    // Version nibble (bits 76..80 counted from the least significant bit) = 8,
    // variant bits (62..64) = 0b10, as RFC 9562 requires for UUIDv8.
    let v = (hash & !(0xf << 76) & !(0b11 << 62)) | (0x8 << 76) | (0b10 << 62);
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        (v >> 96) as u32,
        (v >> 80) as u16,
        (v >> 64) as u16,
        (v >> 48) as u16,
        v & 0xffff_ffff_ffff
    )
}

/// The GUID of a model description, computed from its text (placeholder
/// included, `\r` ignored).
pub fn guid_for_xml(xml: &str) -> String {
    format_guid(fnv1a_128(xml.bytes().filter(|&b| b != b'\r')))
}

/// The model description with the placeholder replaced by `guid`. Returns
/// `None` if the placeholder does not occur exactly once.
pub fn substitute_guid(xml: &str, guid: &str) -> Option<String> {
    (xml.matches(GUID_PLACEHOLDER).count() == 1).then(|| xml.replacen(GUID_PLACEHOLDER, guid, 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_128_known_values() {
        // Reference values of the FNV-1a 128-bit hash.
        assert_eq!(fnv1a_128(*b""), 0x6c62272e07bb014262b821756295c58d);
        assert_eq!(fnv1a_128(*b"a"), 0xd228cb696f1a8caf78912b704e4a8964);
    }

    #[test]
    fn guid_shape_and_stability() {
        let g = guid_for_xml("<a guid=\"@GUID@\"/>\n");
        assert_eq!(g.len(), 38);
        assert!(g.starts_with('{') && g.ends_with('}'));
        assert_eq!(&g[15..16], "8", "version nibble");
        assert!(matches!(&g[20..21], "8" | "9" | "a" | "b"), "variant bits");
        assert_eq!(g, guid_for_xml("<a guid=\"@GUID@\"/>\r\n"));
        assert_ne!(g, guid_for_xml("<a guid=\"@GUID@\"/>"));
    }

    #[test]
    fn substitution_needs_exactly_one_placeholder() {
        assert_eq!(substitute_guid("x@GUID@y", "{g}").as_deref(), Some("x{g}y"));
        assert_eq!(substitute_guid("xy", "{g}"), None);
        assert_eq!(substitute_guid("@GUID@@GUID@", "{g}"), None);
    }
}
