//! Whatever a user types into an angle, number, list or range: the parsers never panic,
//! and what they accept is finite.

use input::text::{
    parse_angle, parse_finite, parse_number_list, parse_range, parse_value, parse_values,
};
use proptest::prelude::*;

proptest! {
    #[test]
    fn any_text_is_parsed_or_refused(text in "[-+0-9.eEpiπdg*/:, a-z]{0,24}") {
        if let Ok(a) = parse_angle(&text) { prop_assert!(a.is_finite()); }
        if let Ok(v) = parse_finite(&text) { prop_assert!(v.is_finite()); }
        if let Ok(list) = parse_number_list(&text) { prop_assert!(list.iter().all(|v| v.is_finite())); }
        if let Ok(v) = parse_value(&text) { prop_assert!(v.is_finite()); }
        if let Ok(range) = parse_range(&text) {
            prop_assert!(range.len() <= 10_000_001 && range.iter().all(|v| v.is_finite()));
        }
        if let Ok(values) = parse_values(&text) { prop_assert!(values.iter().all(|v| v.is_finite())); }
        // A single value reads the same alone and as a range's only item.
        if let Ok(v) = parse_value(&text) {
            if !text.contains(':') && !text.contains(',') {
                prop_assert_eq!(parse_range(&text), Ok(vec![v]));
            }
        }
    }
}
