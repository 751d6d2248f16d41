//! Reading results back from the GPU: a texture's texels (of `f32` values, or any), a buffer of
//! `u64`s, each after submitting the commands that fill it and waiting for them.

use crate::context::{GpuContext, GpuError};

/// Copies an `R32Float` texture into a buffer, submits `enc` and waits for the values.
pub fn read_r32f(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    w: u32,
    h: u32,
) -> Result<Vec<f32>, GpuError> {
    let bytes = read_texels(ctx, enc, (texture, wgpu::TextureAspect::All), (w, h), 4)?;
    Ok(bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect())
}

/// Copies `w x h` texels of `texel_bytes` bytes each of one aspect of a texture (usage
/// `COPY_SRC`) into a buffer, submits `enc` and waits for them: their bytes, row after row.
pub fn read_texels(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    (texture, aspect): (&wgpu::Texture, wgpu::TextureAspect),
    (w, h): (u32, u32),
    texel_bytes: u32,
) -> Result<Vec<u8>, GpuError> {
    let row = (w * texel_bytes).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: row as u64 * h as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    enc.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
    let encoder = std::mem::replace(enc, ctx.device.create_command_encoder(&Default::default()));
    ctx.queue.submit([encoder.finish()]);
    let bytes = map_read(ctx, &buffer)?;
    let used = (w * texel_bytes) as usize;
    Ok((0..h as usize)
        .flat_map(|y| {
            bytes[y * row as usize..y * row as usize + used]
                .iter()
                .copied()
        })
        .collect())
}

/// Maps a buffer whose copies were submitted, waits, and returns its bytes.
pub fn map_read(ctx: &GpuContext, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
    let err = |stage| {
        move |e: &dyn std::fmt::Display| GpuError::Readback {
            stage,
            reason: e.to_string(),
        }
    };
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    ctx.device
        .poll(wgpu::PollType::Wait {
            submission_index: None,
            timeout: None,
        })
        .map_err(|e| err("waiting for the device")(&e))?;
    let mapping = "mapping the buffer";
    rx.recv()
        .map_err(|e| err(mapping)(&e))?
        .map_err(|e| err(mapping)(&e))?;
    let bytes = slice
        .get_mapped_range()
        .map_err(|e| err("viewing the mapped buffer")(&e))?
        .to_vec();
    buffer.unmap();
    Ok(bytes)
}

/// Maps a (submitted) buffer and reads it as `u64`s.
pub fn read_u64(ctx: &GpuContext, buffer: &wgpu::Buffer) -> Result<Vec<u64>, GpuError> {
    Ok(map_read(ctx, buffer)?
        .chunks_exact(8)
        .map(|c| u64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect())
}
