//! The kind of a property value, inferred from its current text, so an edit cannot turn a
//! number into a word or change how many numbers a vector property holds.

/// What a property's text holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PropertyKind {
    /// Whitespace-separated numbers (a scalar is a list of one).
    Numbers(usize),
    /// `true` or `false`.
    Boolean,
    /// Anything else (names, paths, file names, empty values).
    Text,
}

impl PropertyKind {
    /// The kind of an existing value.
    pub fn of(value: &str) -> PropertyKind {
        let tokens: Vec<&str> = value.split_whitespace().collect();
        if matches!(tokens.as_slice(), ["true"] | ["false"]) {
            PropertyKind::Boolean
        } else if !tokens.is_empty() && tokens.iter().all(|t| t.parse::<f64>().is_ok()) {
            PropertyKind::Numbers(tokens.len())
        } else {
            PropertyKind::Text
        }
    }

    /// Whether `value` may replace a value of this kind.
    pub fn accepts(&self, value: &str) -> bool {
        match self {
            PropertyKind::Text => true,
            kind => PropertyKind::of(value) == *kind,
        }
    }

    /// Words for messages: "3 numbers", "true or false".
    pub fn describe(&self) -> String {
        match self {
            PropertyKind::Numbers(1) => "a number".into(),
            PropertyKind::Numbers(n) => format!("{n} numbers"),
            PropertyKind::Boolean => "true or false".into(),
            PropertyKind::Text => "text".into(),
        }
    }
}

/// Numbers separated by single spaces, each in the shortest form that reads back exactly.
pub fn format_numbers(values: &[f64]) -> String {
    values.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_follow_the_text() {
        assert_eq!(PropertyKind::of(" 0.1 0.2 0.3 "), PropertyKind::Numbers(3));
        assert_eq!(PropertyKind::of("true"), PropertyKind::Boolean);
        assert_eq!(PropertyKind::of("femur_r"), PropertyKind::Text);
        assert_eq!(PropertyKind::of(""), PropertyKind::Text);
        assert!(PropertyKind::Numbers(1).accepts("1e-05"));
        assert!(!PropertyKind::Numbers(3).accepts("1 2"));
        assert!(!PropertyKind::Numbers(1).accepts("abc"));
        assert!(!PropertyKind::Boolean.accepts("yes"));
    }
}
