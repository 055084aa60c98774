//! The error a user caused: a missing or malformed file, impossible geometry, absurd settings.
//! The binary prints it as one line and exits with code 2; every other failure exits with 1.

/// Bad input, explained in one line.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

impl InputError {
    pub fn new(message: impl Into<String>) -> Self {
        InputError(message.into())
    }
}

/// Shorthand for returning an [`InputError`] from a function returning `anyhow::Result`.
#[macro_export]
macro_rules! bad_input {
    ($($arg:tt)*) => {
        return Err(anyhow::Error::new($crate::error::InputError(format!($($arg)*))))
    };
}

/// The message a panic carried (its `&str` or `String` payload).
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "an unknown panic".to_string()
    }
    .lines()
    .next()
    .unwrap_or_default()
    .to_string()
}

/// Run a library call that may panic on input it should have rejected; its panic becomes an
/// [`InputError`] saying `what` failed.
pub fn catch_library_panic<T>(
    what: &str,
    call: impl FnOnce() -> Result<T, InputError>,
) -> Result<T, InputError> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(call)).unwrap_or_else(|payload| {
        Err(InputError::new(format!(
            "{what} failed on this input ({}); the file is malformed",
            panic_message(payload.as_ref())
        )))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_library_panic_becomes_one_input_error_line() {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(|_| {}));
        let result: Result<(), InputError> =
            catch_library_panic("the reader", || panic!("index out of bounds\nsecond line"));
        std::panic::set_hook(previous);
        let err = result.unwrap_err();
        assert_eq!(
            err.0,
            "the reader failed on this input (index out of bounds); the file is malformed"
        );
        assert_eq!(catch_library_panic("x", || Ok(3)).ok(), Some(3));
    }
}
