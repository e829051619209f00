//! How the command line reads numbers: every numeric flag through one of
//! these, so that a refused value is answered in words with the flag's
//! own range ("use a whole number from 1 to 100000"), never with an
//! integer type's limits or the parser's vocabulary. Negative values reach
//! them (each flag allows them), so `--every -1` is refused as a number,
//! not taken for an unknown flag.
//!
//! The ranges are the same constants the library's checks use; those
//! checks stay, for callers of the library.

/// A whole number in `lo..=hi`, as `T`.
pub fn whole<T>(lo: u64, hi: u64) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync
where
    T: TryFrom<u64> + Clone + Send + Sync + 'static,
{
    move |text: &str| {
        let fix = if hi == u64::MAX {
            format!("use a whole number, {lo} or more")
        } else {
            format!("use a whole number from {lo} to {hi}")
        };
        let t = text.trim();
        // Digits only (no sign, point or exponent): anything else is not a
        // whole number, and a run of digits too long for u64 is too large.
        if t.is_empty() || !t.bytes().all(|b| b.is_ascii_digit()) {
            return Err(fix);
        }
        let value = t.parse::<u64>().map_err(|_| fix.clone())?;
        if !(lo..=hi).contains(&value) {
            return Err(fix);
        }
        T::try_from(value).map_err(|_| fix)
    }
}

/// A seed: any whole number a 64-bit seed holds.
pub fn seed(text: &str) -> Result<u64, String> {
    whole::<u64>(0, u64::MAX)(text)
        .map_err(|_| "use a whole number from 0 to 18446744073709551615 (2^64 - 1)".into())
}

/// A finite decimal number (its range is the flag's own check's).
pub fn decimal<T: From<f32> + Clone + Send + Sync + 'static>(text: &str) -> Result<T, String> {
    match text.trim().parse::<f32>() {
        Ok(v) if v.is_finite() => Ok(T::from(v)),
        _ => Err("use a number, e.g. 2.5".into()),
    }
}

/// A finite number of seconds, as f64.
pub fn seconds(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err("use a number of seconds, e.g. 2.5".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whole_numbers_are_refused_with_the_flag_range_in_words() {
        let frames = whole::<u32>(1, 100_000);
        assert_eq!(frames("12"), Ok(12));
        assert_eq!(frames(" 100000 "), Ok(100_000));
        for bad in [
            "-1",
            "0",
            "100001",
            "1.5",
            "1e3",
            "abc",
            "",
            "+3",
            "99999999999999999999999",
        ] {
            assert_eq!(
                frames(bad),
                Err("use a whole number from 1 to 100000".to_string()),
                "{bad}"
            );
        }
        // A range past the type's: refused, in the flag's words.
        assert!(whole::<u32>(0, u64::MAX)("4294967296").is_err());
        assert_eq!(seed("18446744073709551615"), Ok(u64::MAX));
        assert!(seed("-1").unwrap_err().contains("from 0 to"));
    }

    #[test]
    fn decimals_must_be_finite_numbers() {
        assert_eq!(decimal::<f32>("2.5"), Ok(2.5));
        assert_eq!(decimal::<f32>("-1"), Ok(-1.0));
        for bad in ["NaN", "inf", "-inf", "abc", "1e99"] {
            assert!(decimal::<f32>(bad).is_err(), "{bad}");
        }
        assert_eq!(seconds("10"), Ok(10.0));
        assert!(seconds("NaN").is_err());
    }
}
