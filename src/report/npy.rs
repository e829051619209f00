//! NumPy's .npy format (version 1.0), little-endian float32, C order: what
//! `numpy.load` reads with no other file. The header is a Python dict
//! literal padded with spaces so that the data starts on a 64-byte boundary.

/// The bytes of a .npy file holding `values`, float32 of `shape`, C order
/// (the last axis fastest). `values.len()` must be the shape's product.
pub fn f32_array(shape: &[usize], values: &[f32]) -> Vec<u8> {
    debug_assert_eq!(shape.iter().product::<usize>(), values.len());
    let dims: Vec<String> = shape.iter().map(|n| n.to_string()).collect();
    // A one-element tuple needs its trailing comma: (n,).
    let tuple = if dims.len() == 1 {
        format!("({},)", dims[0])
    } else {
        format!("({})", dims.join(", "))
    };
    let mut header = format!("{{'descr': '<f4', 'fortran_order': False, 'shape': {tuple}, }}");
    // Magic (6) + version (2) + header length (2) + header + '\n'.
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat(unpadded.next_multiple_of(64) - unpadded));
    header.push('\n');
    let mut bytes = Vec::with_capacity(10 + header.len() + 4 * values.len());
    bytes.extend_from_slice(b"\x93NUMPY\x01\x00");
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    for v in values {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_header_is_numpys_and_the_data_starts_aligned() {
        let bytes = f32_array(&[2, 1, 3, 3], &[1.5; 18]);
        assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
        let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        assert_eq!((10 + len) % 64, 0);
        let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
        assert!(
            header.starts_with("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 1, 3, 3), }")
        );
        assert!(header.ends_with('\n'));
        assert_eq!(bytes.len(), 10 + len + 18 * 4);
        assert_eq!(&bytes[10 + len..14 + len], &1.5f32.to_le_bytes());
        let one = f32_array(&[3], &[0.0; 3]);
        assert!(std::str::from_utf8(&one[10..])
            .unwrap()
            .contains("'shape': (3,),"));
    }
}
