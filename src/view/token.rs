//! The access token of a preview server: 128 random bits from the operating system, shown once
//! in the URL the server prints, compared in constant time.

use crate::{Error, Result};

/// A secret the client must present.
#[derive(Clone, PartialEq, Eq)]
pub struct Token(String);

impl std::fmt::Debug for Token {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Token(…)")
    }
}

impl Token {
    /// 16 bytes of the operating system's random source (`getrandom`: the `getrandom` system
    /// call on Linux, `/dev/urandom` where that is missing, `ProcessPrng` on Windows, ...) as
    /// 32 lower-case hex digits.
    ///
    /// # Errors
    /// [`Error::Io`] if the operating system gives no random bytes.
    pub fn random() -> Result<Token> {
        let mut bytes = [0u8; 16];
        getrandom::fill(&mut bytes).map_err(|e| {
            Error::io(
                "the operating system's random source",
                std::io::Error::other(e.to_string()),
            )
        })?;
        Ok(Token(bytes.iter().map(|b| format!("{b:02x}")).collect()))
    }

    /// A fixed token (tests).
    pub fn fixed(s: &str) -> Token {
        Token(s.to_string())
    }

    /// The token's text, for the URL.
    pub fn as_str(&self) -> &str {
        &self.0
    }

    /// True if `given` is this token. Takes the same time whatever the first differing byte
    /// (it depends only on the lengths), so timing does not reveal a prefix.
    pub fn matches(&self, given: &str) -> bool {
        let (a, b) = (self.0.as_bytes(), given.as_bytes());
        let mut diff = (a.len() != b.len()) as u8;
        for (i, x) in a.iter().enumerate() {
            diff |= x ^ b.get(i).copied().unwrap_or(0);
        }
        std::hint::black_box(diff) == 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn random_tokens_are_32_hex_digits_and_differ() {
        let (a, b) = (Token::random().unwrap(), Token::random().unwrap());
        assert_eq!(a.as_str().len(), 32);
        assert!(a.as_str().bytes().all(|c| c.is_ascii_hexdigit()));
        assert_ne!(a, b);
        assert_eq!(format!("{a:?}"), "Token(…)");
    }

    #[test]
    fn only_the_exact_token_matches() {
        let t = Token::fixed("0123abcd");
        assert!(t.matches("0123abcd"));
        for wrong in [
            "",
            "0123abc",
            "0123abcd0",
            "1123abcd",
            "0123abce",
            "0123ABCD",
        ] {
            assert!(!t.matches(wrong), "{wrong}");
        }
    }
}
