//! Deterministic GUIDs: a 128-bit FNV-1a hash of the model description, formatted as a UUID.
//! The same scene and the same flexfmu variable table always give the same GUID; any change
//! to the variables gives another, so an FMU never runs with a library that disagrees with it.

/// 128-bit FNV-1a hash.
pub fn fnv1a_128(data: &[u8]) -> u128 {
    const OFFSET: u128 = 0x6c62272e07bb014262b821756295c58d;
    const PRIME: u128 = 0x0000000001000000000000000000013B;
    let mut h = OFFSET;
    for &b in data {
        h ^= u128::from(b);
        h = h.wrapping_mul(PRIME);
    }
    h
}

/// 64-bit FNV-1a hash (checksums of serialized FMU states).
pub fn fnv1a_64(data: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    for &b in data {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x100000001b3);
    }
    h
}

/// `{xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx}` from the hash of `data`.
pub fn guid_of(data: &[u8]) -> String {
    let h = fnv1a_128(data);
    let hex = format!("{h:032x}");
    format!(
        "{{{}-{}-{}-{}-{}}}",
        &hex[0..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..32]
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_fnv_vectors() {
        // FNV-1a 128 reference values (offset basis for the empty input).
        assert_eq!(fnv1a_128(b""), 0x6c62272e07bb014262b821756295c58d);
        assert_eq!(fnv1a_128(b"a"), 0xd228cb696f1a8caf78912b704e4a8964);
        let g = guid_of(b"x");
        assert_eq!(g.len(), 38);
        assert_ne!(guid_of(b"x"), guid_of(b"y"));
        assert_eq!(fnv1a_64(b"a"), 0xaf63dc4c8601ec8c);
    }
}
