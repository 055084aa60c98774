//! A small SPIR-V reader: the descriptor bindings (and which of them the shader may write), the
//! push-constant block's size and member layout, and the workgroup size a shader declares.
//! Pipelines are built from this, and every pass's bindings and push constants are checked
//! against it.

use std::collections::HashMap;

/// The kind of a descriptor binding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DescriptorKind {
    StorageBuffer,
    UniformBuffer,
    StorageImage,
    SampledImage,
    CombinedImageSampler,
    Sampler,
    /// A buffer read through a typed view with texel fetches (`samplerBuffer`).
    UniformTexelBuffer,
    /// A buffer read and written through a typed view (`imageBuffer`). Told apart so that a
    /// shader declaring one gets its own descriptor type; no `Binding` binds one yet, so a pass
    /// over such a shader is refused by the interface check.
    StorageTexelBuffer,
}

impl DescriptorKind {
    pub fn name(self) -> &'static str {
        match self {
            DescriptorKind::StorageBuffer => "storage buffer",
            DescriptorKind::UniformBuffer => "uniform buffer",
            DescriptorKind::StorageImage => "storage image",
            DescriptorKind::SampledImage => "sampled image",
            DescriptorKind::CombinedImageSampler => "combined image sampler",
            DescriptorKind::Sampler => "sampler",
            DescriptorKind::UniformTexelBuffer => "uniform texel buffer",
            DescriptorKind::StorageTexelBuffer => "storage texel buffer",
        }
    }
}

/// What one shader stage declares.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ShaderInterface {
    /// (binding, kind) in set 0, sorted by binding.
    pub bindings: Vec<(u32, DescriptorKind)>,
    /// Bindings of storage buffers and images the shader may write (not declared `readonly`).
    pub writable: Vec<u32>,
    /// Size of the push-constant block in bytes (0 if none).
    pub push_constant_size: u32,
    /// (offset, size) in bytes of each member of the push-constant block, in declaration order.
    pub push_constant_members: Vec<(u32, u32)>,
    /// The compute workgroup size from `LocalSize` (None for other stages or `LocalSizeId`).
    pub local_size: Option<[u32; 3]>,
    /// Specialization-constant IDs whose values set the workgroup size (from `LocalSizeId` or
    /// the WorkgroupSize built-in), per axis.
    pub local_size_spec_ids: [Option<u32>; 3],
}

impl ShaderInterface {
    /// Merge the interface of another stage of the same pipeline.
    pub fn merge(&mut self, other: &ShaderInterface) -> Result<(), String> {
        for &(binding, kind) in &other.bindings {
            match self.bindings.iter().find(|(b, _)| *b == binding) {
                Some(&(_, existing)) if existing != kind => {
                    return Err(format!(
                        "binding {binding} is a {} in one stage and a {} in another",
                        existing.name(),
                        kind.name()
                    ));
                }
                Some(_) => {}
                None => self.bindings.push((binding, kind)),
            }
        }
        self.bindings.sort_by_key(|b| b.0);
        for &binding in &other.writable {
            if !self.writable.contains(&binding) {
                self.writable.push(binding);
            }
        }
        self.writable.sort_unstable();
        if other.push_constant_size > self.push_constant_size {
            self.push_constant_size = other.push_constant_size;
            self.push_constant_members = other.push_constant_members.clone();
        }
        Ok(())
    }
}

const OP_ENTRY_POINT: u32 = 15;
const OP_EXECUTION_MODE: u32 = 16;
const OP_TYPE_INT: u32 = 21;
const OP_TYPE_FLOAT: u32 = 22;
const OP_TYPE_VECTOR: u32 = 23;
const OP_TYPE_MATRIX: u32 = 24;
const OP_TYPE_IMAGE: u32 = 25;
const OP_TYPE_SAMPLER: u32 = 26;
const OP_TYPE_SAMPLED_IMAGE: u32 = 27;
const OP_TYPE_ARRAY: u32 = 28;
const OP_TYPE_RUNTIME_ARRAY: u32 = 29;
const OP_TYPE_STRUCT: u32 = 30;
const OP_TYPE_POINTER: u32 = 32;
const OP_CONSTANT: u32 = 43;
const OP_SPEC_CONSTANT: u32 = 50;
const OP_SPEC_CONSTANT_COMPOSITE: u32 = 51;
const OP_VARIABLE: u32 = 59;
const OP_DECORATE: u32 = 71;
const OP_MEMBER_DECORATE: u32 = 72;
const OP_EXECUTION_MODE_ID: u32 = 331;

const DECORATION_SPEC_ID: u32 = 1;
const DECORATION_BLOCK: u32 = 2;
const DECORATION_BUFFER_BLOCK: u32 = 3;
const DECORATION_ARRAY_STRIDE: u32 = 6;
const DECORATION_MATRIX_STRIDE: u32 = 7;
const DECORATION_BUILTIN: u32 = 11;
const DECORATION_NON_WRITABLE: u32 = 24;
const DECORATION_BINDING: u32 = 33;
const DECORATION_DESCRIPTOR_SET: u32 = 34;
const DECORATION_OFFSET: u32 = 35;

const DIM_BUFFER: u32 = 5;

const BUILTIN_WORKGROUP_SIZE: u32 = 25;
const MODE_LOCAL_SIZE: u32 = 17;
const MODE_LOCAL_SIZE_ID: u32 = 38;

const STORAGE_UNIFORM_CONSTANT: u32 = 0;
const STORAGE_UNIFORM: u32 = 2;
const STORAGE_PUSH_CONSTANT: u32 = 9;
const STORAGE_STORAGE_BUFFER: u32 = 12;

#[derive(Clone, Debug)]
enum Type {
    Scalar { bytes: u32 },
    Vector { component: u32, count: u32 },
    Matrix { column: u32, count: u32 },
    Image { sampled: u32, dim: u32 },
    Sampler,
    SampledImage { image: u32 },
    Array { element: u32, length_id: u32 },
    RuntimeArray,
    Struct { members: Vec<u32> },
    Pointer { pointee: u32 },
}

/// Read the interface of a SPIR-V module.
pub fn reflect(words: &[u32]) -> Result<ShaderInterface, String> {
    if words.len() < 5 || words[0] != 0x0723_0203 {
        return Err("not a SPIR-V module (bad magic number)".into());
    }
    let mut types: HashMap<u32, Type> = HashMap::new();
    let mut constants: HashMap<u32, u32> = HashMap::new();
    let mut spec_ids: HashMap<u32, u32> = HashMap::new();
    let mut bindings: HashMap<u32, u32> = HashMap::new();
    let mut sets: HashMap<u32, u32> = HashMap::new();
    let mut blocks: HashMap<u32, u32> = HashMap::new();
    let mut array_strides: HashMap<u32, u32> = HashMap::new();
    let mut matrix_strides: HashMap<(u32, u32), u32> = HashMap::new();
    let mut offsets: HashMap<(u32, u32), u32> = HashMap::new();
    let mut non_writable: Vec<u32> = Vec::new();
    let mut non_writable_members: Vec<(u32, u32)> = Vec::new();
    let mut workgroup_builtin: Option<u32> = None;
    let mut composites: HashMap<u32, Vec<u32>> = HashMap::new();
    let mut variables: Vec<(u32, u32, u32)> = Vec::new(); // (type, id, storage)
    let mut local_size = None;
    let mut local_size_ids: Option<[u32; 3]> = None;

    let mut i = 5;
    while i < words.len() {
        let count = (words[i] >> 16) as usize;
        let opcode = words[i] & 0xffff;
        if count == 0 || i + count > words.len() {
            return Err(format!("malformed instruction at word {i}"));
        }
        let op = &words[i + 1..i + count];
        match opcode {
            OP_EXECUTION_MODE if op.len() >= 5 && op[1] == MODE_LOCAL_SIZE => {
                local_size = Some([op[2], op[3], op[4]]);
            }
            OP_EXECUTION_MODE_ID if op.len() >= 5 && op[1] == MODE_LOCAL_SIZE_ID => {
                local_size_ids = Some([op[2], op[3], op[4]]);
            }
            OP_TYPE_INT | OP_TYPE_FLOAT => {
                types.insert(op[0], Type::Scalar { bytes: op[1] / 8 });
            }
            OP_TYPE_VECTOR => {
                types.insert(
                    op[0],
                    Type::Vector {
                        component: op[1],
                        count: op[2],
                    },
                );
            }
            OP_TYPE_MATRIX => {
                types.insert(
                    op[0],
                    Type::Matrix {
                        column: op[1],
                        count: op[2],
                    },
                );
            }
            OP_TYPE_IMAGE => {
                types.insert(
                    op[0],
                    Type::Image {
                        sampled: op[6],
                        dim: op[2],
                    },
                );
            }
            OP_TYPE_SAMPLER => {
                types.insert(op[0], Type::Sampler);
            }
            OP_TYPE_SAMPLED_IMAGE => {
                types.insert(op[0], Type::SampledImage { image: op[1] });
            }
            OP_TYPE_ARRAY => {
                types.insert(
                    op[0],
                    Type::Array {
                        element: op[1],
                        length_id: op[2],
                    },
                );
            }
            OP_TYPE_RUNTIME_ARRAY => {
                types.insert(op[0], Type::RuntimeArray);
            }
            OP_TYPE_STRUCT => {
                types.insert(
                    op[0],
                    Type::Struct {
                        members: op[1..].to_vec(),
                    },
                );
            }
            OP_TYPE_POINTER => {
                types.insert(op[0], Type::Pointer { pointee: op[2] });
            }
            OP_CONSTANT | OP_SPEC_CONSTANT if op.len() >= 3 => {
                constants.insert(op[1], op[2]);
            }
            OP_SPEC_CONSTANT_COMPOSITE => {
                composites.insert(op[1], op[2..].to_vec());
            }
            OP_VARIABLE => variables.push((op[0], op[1], op[2])),
            OP_DECORATE if op.len() >= 2 => {
                let value = op.get(2).copied().unwrap_or(0);
                match op[1] {
                    DECORATION_BINDING => {
                        bindings.insert(op[0], value);
                    }
                    DECORATION_DESCRIPTOR_SET => {
                        sets.insert(op[0], value);
                    }
                    DECORATION_BLOCK | DECORATION_BUFFER_BLOCK => {
                        blocks.insert(op[0], op[1]);
                    }
                    DECORATION_ARRAY_STRIDE => {
                        array_strides.insert(op[0], value);
                    }
                    DECORATION_SPEC_ID => {
                        spec_ids.insert(op[0], value);
                    }
                    DECORATION_BUILTIN if value == BUILTIN_WORKGROUP_SIZE => {
                        workgroup_builtin = Some(op[0]);
                    }
                    DECORATION_NON_WRITABLE => non_writable.push(op[0]),
                    _ => {}
                }
            }
            OP_MEMBER_DECORATE if op.len() >= 4 => match op[2] {
                DECORATION_OFFSET => {
                    offsets.insert((op[0], op[1]), op[3]);
                }
                DECORATION_MATRIX_STRIDE => {
                    matrix_strides.insert((op[0], op[1]), op[3]);
                }
                _ => {}
            },
            OP_MEMBER_DECORATE if op.len() == 3 && op[2] == DECORATION_NON_WRITABLE => {
                non_writable_members.push((op[0], op[1]));
            }
            OP_ENTRY_POINT => {}
            _ => {}
        }
        i += count;
    }

    let layout = Layout {
        types: &types,
        constants: &constants,
        array_strides: &array_strides,
        matrix_strides: &matrix_strides,
        offsets: &offsets,
    };
    let mut interface = ShaderInterface {
        local_size,
        ..Default::default()
    };
    let spec_axes = local_size_ids
        .map(|ids| ids.to_vec())
        .or_else(|| workgroup_builtin.and_then(|id| composites.get(&id).cloned()));
    if let Some(axes) = spec_axes {
        for (axis, id) in axes.iter().take(3).enumerate() {
            interface.local_size_spec_ids[axis] = spec_ids.get(id).copied();
        }
        // The WorkgroupSize built-in (or LocalSizeId) overrides any LocalSize mode; its default
        // values are those of the constants it is made of.
        let sizes: Option<Vec<u32>> = axes
            .iter()
            .take(3)
            .map(|id| constants.get(id).copied())
            .collect();
        if let Some(s) = sizes.filter(|s| s.len() == 3) {
            interface.local_size = Some([s[0], s[1], s[2]]);
        }
    }

    for &(type_id, id, storage) in &variables {
        let Some(Type::Pointer { pointee, .. }) = types.get(&type_id) else {
            continue;
        };
        let pointee = *pointee;
        if storage == STORAGE_PUSH_CONSTANT {
            interface.push_constant_size = layout.size_of(pointee, None)?;
            interface.push_constant_members = layout.members(pointee)?;
            continue;
        }
        let kind = match storage {
            STORAGE_STORAGE_BUFFER => DescriptorKind::StorageBuffer,
            STORAGE_UNIFORM => match blocks.get(&pointee) {
                Some(&DECORATION_BUFFER_BLOCK) => DescriptorKind::StorageBuffer,
                _ => DescriptorKind::UniformBuffer,
            },
            STORAGE_UNIFORM_CONSTANT => match types.get(&pointee) {
                Some(&Type::Image { sampled, dim }) => match (sampled, dim) {
                    (2, DIM_BUFFER) => DescriptorKind::StorageTexelBuffer,
                    (_, DIM_BUFFER) => DescriptorKind::UniformTexelBuffer,
                    (2, _) => DescriptorKind::StorageImage,
                    _ => DescriptorKind::SampledImage,
                },
                Some(Type::SampledImage { image }) => match types.get(image) {
                    Some(Type::Image {
                        dim: DIM_BUFFER, ..
                    }) => DescriptorKind::UniformTexelBuffer,
                    _ => DescriptorKind::CombinedImageSampler,
                },
                Some(Type::Sampler) => DescriptorKind::Sampler,
                Some(Type::Array { .. }) | Some(Type::RuntimeArray) => {
                    return Err(format!(
                        "variable %{id}: descriptor arrays are not supported"
                    ));
                }
                _ => continue,
            },
            _ => continue,
        };
        let set = sets.get(&id).copied().unwrap_or(0);
        if set != 0 {
            return Err(format!(
                "variable %{id} uses descriptor set {set}; vkgi uses set 0 only"
            ));
        }
        let binding = bindings
            .get(&id)
            .copied()
            .ok_or_else(|| format!("variable %{id} has no binding decoration"))?;
        if interface.bindings.iter().any(|(b, _)| *b == binding) {
            return Err(format!("binding {binding} is declared twice"));
        }
        let read_only = non_writable.contains(&id)
            || match types.get(&pointee) {
                Some(Type::Struct { members }) => {
                    (0..members.len() as u32).all(|m| non_writable_members.contains(&(pointee, m)))
                }
                _ => false,
            };
        let storage_kind = matches!(
            kind,
            DescriptorKind::StorageBuffer
                | DescriptorKind::StorageImage
                | DescriptorKind::StorageTexelBuffer
        );
        if storage_kind && !read_only {
            interface.writable.push(binding);
        }
        interface.bindings.push((binding, kind));
    }
    interface.bindings.sort_by_key(|b| b.0);
    interface.writable.sort_unstable();
    Ok(interface)
}

struct Layout<'a> {
    types: &'a HashMap<u32, Type>,
    constants: &'a HashMap<u32, u32>,
    array_strides: &'a HashMap<u32, u32>,
    matrix_strides: &'a HashMap<(u32, u32), u32>,
    offsets: &'a HashMap<(u32, u32), u32>,
}

impl Layout<'_> {
    /// (offset, size) of each member of struct `id`, in declaration order.
    fn members(&self, id: u32) -> Result<Vec<(u32, u32)>, String> {
        let Some(Type::Struct { members }) = self.types.get(&id) else {
            return Err(format!("type %{id} is not a struct"));
        };
        let mut layout = Vec::with_capacity(members.len());
        let mut end = 0;
        for (index, &member) in members.iter().enumerate() {
            let key = (id, index as u32);
            let offset = self.offsets.get(&key).copied().unwrap_or(end);
            let size = self.size_of(member, self.matrix_strides.get(&key).copied())?;
            end = offset + size;
            layout.push((offset, size));
        }
        Ok(layout)
    }

    /// Size in bytes of a type laid out with explicit offsets and strides (a block member).
    /// `matrix_stride` is the stride of a matrix member when known.
    fn size_of(&self, id: u32, matrix_stride: Option<u32>) -> Result<u32, String> {
        let ty = self
            .types
            .get(&id)
            .ok_or_else(|| format!("unknown type %{id}"))?;
        Ok(match ty {
            Type::Scalar { bytes } => *bytes,
            Type::Vector { component, count } => self.size_of(*component, None)? * count,
            Type::Matrix { column, count } => {
                let stride = match matrix_stride {
                    Some(s) => s,
                    None => self.size_of(*column, None)?,
                };
                stride * count
            }
            Type::Array { element, length_id } => {
                let length = self
                    .constants
                    .get(length_id)
                    .copied()
                    .ok_or_else(|| format!("array %{id} has a non-constant length"))?;
                let stride = match self.array_strides.get(&id) {
                    Some(&s) => s,
                    None => self.size_of(*element, None)?,
                };
                stride * length
            }
            Type::Struct { members } => {
                let mut end = 0;
                for (index, &member) in members.iter().enumerate() {
                    let key = (id, index as u32);
                    let offset = self.offsets.get(&key).copied().unwrap_or(end);
                    let size = self.size_of(member, self.matrix_strides.get(&key).copied())?;
                    end = end.max(offset + size);
                }
                end
            }
            other => return Err(format!("type %{id} ({other:?}) has no size in a block")),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spirv(parts: &[&[u32]]) -> Vec<u32> {
        let mut words = vec![0x0723_0203, 0x0001_0500, 0, 100, 0];
        for p in parts {
            words.push(((p.len() as u32) << 16) | p[0]);
            words.extend_from_slice(&p[1..]);
        }
        words
    }

    #[test]
    fn rejects_garbage() {
        assert!(reflect(&[1, 2, 3]).is_err());
        assert!(reflect(&[0x0723_0203, 0, 0, 0, 0, 0x0005_0010]).is_err());
    }

    #[test]
    fn reads_bindings_push_constants_and_local_size() {
        // %1 = float, %2 = vec4, %3 = struct{vec4, float} (Block), %4 = ptr PushConstant %3,
        // %5 = var push; %6 = image(storage), %7 = ptr UniformConstant %6, %8 = var binding 3;
        // %9 = struct{runtime array} in StorageBuffer at binding 1.
        let words = spirv(&[
            &[OP_EXECUTION_MODE, 20, MODE_LOCAL_SIZE, 8, 4, 2],
            &[OP_DECORATE, 3, DECORATION_BLOCK],
            &[OP_MEMBER_DECORATE, 3, 0, DECORATION_OFFSET, 0],
            &[OP_MEMBER_DECORATE, 3, 1, DECORATION_OFFSET, 16],
            &[OP_DECORATE, 8, DECORATION_BINDING, 3],
            &[OP_DECORATE, 8, DECORATION_DESCRIPTOR_SET, 0],
            &[OP_DECORATE, 8, DECORATION_NON_WRITABLE],
            &[OP_DECORATE, 11, DECORATION_BINDING, 1],
            &[OP_DECORATE, 9, DECORATION_BLOCK],
            &[OP_TYPE_FLOAT, 1, 32],
            &[OP_TYPE_VECTOR, 2, 1, 4],
            &[OP_TYPE_STRUCT, 3, 2, 1],
            &[OP_TYPE_POINTER, 4, STORAGE_PUSH_CONSTANT, 3],
            &[OP_VARIABLE, 4, 5, STORAGE_PUSH_CONSTANT],
            &[OP_TYPE_IMAGE, 6, 1, 1, 0, 0, 0, 2, 1],
            &[OP_TYPE_POINTER, 7, STORAGE_UNIFORM_CONSTANT, 6],
            &[OP_VARIABLE, 7, 8, STORAGE_UNIFORM_CONSTANT],
            &[OP_TYPE_RUNTIME_ARRAY, 12, 2],
            &[OP_TYPE_STRUCT, 9, 12],
            &[OP_TYPE_POINTER, 10, STORAGE_STORAGE_BUFFER, 9],
            &[OP_VARIABLE, 10, 11, STORAGE_STORAGE_BUFFER],
        ]);
        let i = match reflect(&words) {
            Ok(i) => i,
            Err(e) => panic!("reflection failed: {e}"),
        };
        assert_eq!(i.local_size, Some([8, 4, 2]));
        assert_eq!(i.push_constant_size, 20);
        assert_eq!(i.push_constant_members, vec![(0, 16), (16, 4)]);
        assert_eq!(
            i.writable,
            vec![1],
            "the image is readonly, the buffer is not"
        );
        assert_eq!(
            i.bindings,
            vec![
                (1, DescriptorKind::StorageBuffer),
                (3, DescriptorKind::StorageImage)
            ]
        );
    }

    #[test]
    fn texel_buffers_are_told_from_images() {
        // %1 = float; %2 = image Buffer sampled, %3 = sampledimage %2 (samplerBuffer) at binding
        // 0; %6 = image Buffer storage (imageBuffer) at binding 1; %9 = image 2D sampled,
        // %10 = sampledimage %9 (sampler2D) at binding 2.
        let words = spirv(&[
            &[OP_DECORATE, 5, DECORATION_BINDING, 0],
            &[OP_DECORATE, 8, DECORATION_BINDING, 1],
            &[OP_DECORATE, 12, DECORATION_BINDING, 2],
            &[OP_TYPE_FLOAT, 1, 32],
            &[OP_TYPE_IMAGE, 2, 1, DIM_BUFFER, 0, 0, 0, 1, 0],
            &[OP_TYPE_SAMPLED_IMAGE, 3, 2],
            &[OP_TYPE_POINTER, 4, STORAGE_UNIFORM_CONSTANT, 3],
            &[OP_VARIABLE, 4, 5, STORAGE_UNIFORM_CONSTANT],
            &[OP_TYPE_IMAGE, 6, 1, DIM_BUFFER, 0, 0, 0, 2, 1],
            &[OP_TYPE_POINTER, 7, STORAGE_UNIFORM_CONSTANT, 6],
            &[OP_VARIABLE, 7, 8, STORAGE_UNIFORM_CONSTANT],
            &[OP_TYPE_IMAGE, 9, 1, 1, 0, 0, 0, 1, 0],
            &[OP_TYPE_SAMPLED_IMAGE, 10, 9],
            &[OP_TYPE_POINTER, 11, STORAGE_UNIFORM_CONSTANT, 10],
            &[OP_VARIABLE, 11, 12, STORAGE_UNIFORM_CONSTANT],
        ]);
        let i = match reflect(&words) {
            Ok(i) => i,
            Err(e) => panic!("reflection failed: {e}"),
        };
        assert_eq!(
            i.bindings,
            vec![
                (0, DescriptorKind::UniformTexelBuffer),
                (1, DescriptorKind::StorageTexelBuffer),
                (2, DescriptorKind::CombinedImageSampler)
            ]
        );
        assert_eq!(i.writable, vec![1], "a storage texel buffer may be written");
    }

    #[test]
    fn a_buffer_whose_members_are_all_readonly_is_not_writable() {
        // %9 = struct{float, float} at binding 0, both members NonWritable; %13 = struct{float}
        // at binding 1, not.
        let words = spirv(&[
            &[OP_DECORATE, 9, DECORATION_BLOCK],
            &[OP_MEMBER_DECORATE, 9, 0, DECORATION_NON_WRITABLE],
            &[OP_MEMBER_DECORATE, 9, 1, DECORATION_NON_WRITABLE],
            &[OP_DECORATE, 11, DECORATION_BINDING, 0],
            &[OP_DECORATE, 13, DECORATION_BLOCK],
            &[OP_DECORATE, 15, DECORATION_BINDING, 1],
            &[OP_TYPE_FLOAT, 1, 32],
            &[OP_TYPE_STRUCT, 9, 1, 1],
            &[OP_TYPE_POINTER, 10, STORAGE_STORAGE_BUFFER, 9],
            &[OP_VARIABLE, 10, 11, STORAGE_STORAGE_BUFFER],
            &[OP_TYPE_STRUCT, 13, 1],
            &[OP_TYPE_POINTER, 14, STORAGE_STORAGE_BUFFER, 13],
            &[OP_VARIABLE, 14, 15, STORAGE_STORAGE_BUFFER],
        ]);
        let i = match reflect(&words) {
            Ok(i) => i,
            Err(e) => panic!("reflection failed: {e}"),
        };
        assert_eq!(i.writable, vec![1]);
    }

    #[test]
    fn merge_detects_conflicting_kinds() {
        let mut a = ShaderInterface {
            bindings: vec![(0, DescriptorKind::StorageBuffer)],
            ..Default::default()
        };
        let b = ShaderInterface {
            bindings: vec![
                (0, DescriptorKind::StorageImage),
                (1, DescriptorKind::UniformBuffer),
            ],
            push_constant_size: 64,
            ..Default::default()
        };
        assert!(a.merge(&b).is_err());
        let c = ShaderInterface {
            bindings: vec![
                (0, DescriptorKind::StorageBuffer),
                (2, DescriptorKind::StorageImage),
            ],
            push_constant_size: 16,
            ..Default::default()
        };
        assert_eq!(a.merge(&c), Ok(()));
        assert_eq!(a.bindings.len(), 2);
        assert_eq!(a.push_constant_size, 16);
    }
}
