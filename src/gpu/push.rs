//! Push constants as Rust structs whose member layout is checked against the shader's: the
//! [`push_constants!`](crate::push_constants) macro declares a `#[repr(C)]` struct and records
//! every member's offset and size, which the recorder compares with the SPIR-V block's.

/// A push-constant block: its bytes and each member's (offset, size) in declaration order.
pub trait PushConstants {
    fn bytes(&self) -> &[u8];
    fn members(&self) -> &'static [(u32, u32)];
}

/// No push constants.
impl PushConstants for () {
    fn bytes(&self) -> &[u8] {
        &[]
    }
    fn members(&self) -> &'static [(u32, u32)] {
        &[]
    }
}

/// Declare a push-constant struct: `#[repr(C)]`, `Pod`, and a [`PushConstants`] impl listing
/// each member's offset and size (checked against the shader when a pass records it).
#[macro_export]
macro_rules! push_constants {
    ($(#[$meta:meta])* $vis:vis struct $name:ident {
        $($(#[$field_meta:meta])* $field_vis:vis $field:ident : $ty:ty),* $(,)?
    }) => {
        $(#[$meta])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
        $vis struct $name {
            $($(#[$field_meta])* $field_vis $field: $ty),*
        }

        impl $crate::gpu::PushConstants for $name {
            fn bytes(&self) -> &[u8] {
                bytemuck::bytes_of(self)
            }
            fn members(&self) -> &'static [(u32, u32)] {
                const MEMBERS: &[(u32, u32)] = &[$((
                    ::std::mem::offset_of!($name, $field) as u32,
                    ::std::mem::size_of::<$ty>() as u32,
                )),*];
                MEMBERS
            }
        }
    };
}

/// Why `push` does not match a shader block of `size` bytes with members `members`, if it
/// does not.
pub fn mismatch(push: &dyn PushConstants, size: u32, members: &[(u32, u32)]) -> Option<String> {
    if push.bytes().len() as u32 != size {
        return Some(format!(
            "push constants are {} bytes in Rust but {size} bytes in the shader",
            push.bytes().len()
        ));
    }
    let rust = push.members();
    if rust.len() != members.len() {
        return Some(format!(
            "the push-constant block has {} members in Rust but {} in the shader",
            rust.len(),
            members.len()
        ));
    }
    rust.iter()
        .zip(members)
        .enumerate()
        .find(|(_, (r, s))| r != s)
        .map(|(index, (r, s))| {
            format!(
                "push-constant member {index} is at offset {} ({} bytes) in Rust but at offset {} ({} bytes) in the shader",
                r.0, r.1, s.0, s.1
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    crate::push_constants! {
        struct Example {
            origin: [f32; 4],
            size: [u32; 2],
            scale: f32,
            count: u32,
        }
    }

    #[test]
    fn members_carry_offsets_and_sizes() {
        let e = Example {
            origin: [0.0; 4],
            size: [1, 2],
            scale: 1.0,
            count: 3,
        };
        assert_eq!(e.members(), &[(0, 16), (16, 8), (24, 4), (28, 4)]);
        assert_eq!(e.bytes().len(), 32);
        assert_eq!(
            mismatch(&e, 32, &[(0, 16), (16, 8), (24, 4), (28, 4)]),
            None
        );
        let moved = mismatch(&e, 32, &[(0, 16), (16, 8), (28, 4), (24, 4)]);
        assert!(moved.is_some_and(|m| m.contains("member 2")));
        assert!(mismatch(&e, 48, &[]).is_some_and(|m| m.contains("bytes")));
        assert_eq!(mismatch(&(), 0, &[]), None);
    }
}
