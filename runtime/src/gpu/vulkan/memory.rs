//! Memory: host-visible mapped buffers ([`Buf`]), `R32_SFLOAT` images
//! ([`Img`]) and their memory types, and the [`VkMesh`] uploads that use
//! them (the stencil table, the displacement map, storage bindings).

use crate::kernels;
use ash::vk;

use super::device::{call, VkError};
use super::{Buf, Img, VkMesh, Vulkan};

impl Default for Img {
    fn default() -> Self {
        Img {
            image: vk::Image::null(),
            memory: vk::DeviceMemory::null(),
            view: vk::ImageView::null(),
        }
    }
}

impl Img {
    pub(super) fn destroy(&self, d: &ash::Device) {
        unsafe {
            d.destroy_image_view(self.view, None);
            d.destroy_image(self.image, None);
            d.free_memory(self.memory, None);
        }
    }
}

impl Buf {
    pub(super) fn write(&self, bytes: &[u8]) {
        let n = bytes.len().min(self.size as usize);
        // SAFETY: `ptr` maps the whole (host-coherent) allocation of at
        // least `size` bytes; no submission is in flight while we write.
        unsafe { std::ptr::copy_nonoverlapping(bytes.as_ptr(), self.ptr, n) };
    }
    pub(super) fn read_f32(&self, floats: usize) -> Vec<f32> {
        let n = floats.min(self.size as usize / 4);
        // SAFETY: as in `write`; the fence wait made the device writes
        // available and the barrier made them visible to the host.
        let bytes = unsafe { std::slice::from_raw_parts(self.ptr, n * 4) };
        bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    }
    pub(super) fn destroy(&self, d: &ash::Device) {
        unsafe {
            d.destroy_buffer(self.buffer, None);
            d.free_memory(self.memory, None);
        }
    }
}

impl Vulkan {
    fn memory_type(
        &self,
        bits: u32,
        want: vk::MemoryPropertyFlags,
        what: &'static str,
    ) -> Result<u32, VkError> {
        (0..self.memory.memory_type_count)
            .find(|&i| {
                bits & (1 << i) != 0
                    && self.memory.memory_types[i as usize]
                        .property_flags
                        .contains(want)
            })
            .ok_or(VkError::NoMemoryType(what))
    }

    /// A host-visible, coherent, persistently mapped buffer.
    pub(super) fn buffer(
        &self,
        what: &'static str,
        size: u64,
        usage: vk::BufferUsageFlags,
    ) -> Result<Buf, VkError> {
        let size = size.max(16);
        let d = &self.device;
        let buffer = unsafe {
            d.create_buffer(
                &vk::BufferCreateInfo::default()
                    .size(size)
                    .usage(usage)
                    .sharing_mode(vk::SharingMode::EXCLUSIVE),
                None,
            )
        }
        .map_err(call("vkCreateBuffer"))?;
        let req = unsafe { d.get_buffer_memory_requirements(buffer) };
        let ty = match self.memory_type(
            req.memory_type_bits,
            vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT,
            what,
        ) {
            Ok(t) => t,
            Err(e) => {
                unsafe { d.destroy_buffer(buffer, None) };
                return Err(e);
            }
        };
        let memory = match unsafe {
            d.allocate_memory(
                &vk::MemoryAllocateInfo::default()
                    .allocation_size(req.size)
                    .memory_type_index(ty),
                None,
            )
        } {
            Ok(m) => m,
            Err(e) => {
                unsafe { d.destroy_buffer(buffer, None) };
                return Err(call("vkAllocateMemory")(e));
            }
        };
        let buf = Buf {
            buffer,
            memory,
            size,
            ptr: std::ptr::null_mut(),
        };
        let bound = unsafe { d.bind_buffer_memory(buffer, memory, 0) }
            .map_err(call("vkBindBufferMemory"))
            .and_then(|_| {
                unsafe { d.map_memory(memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty()) }
                    .map_err(call("vkMapMemory"))
            });
        match bound {
            Ok(ptr) => Ok(Buf {
                ptr: ptr as *mut u8,
                ..buf
            }),
            Err(e) => {
                buf.destroy(d);
                Err(e)
            }
        }
    }
}

impl<'v> VkMesh<'v> {
    /// An `R32_SFLOAT` image of `width × height` texels (row-major), in
    /// shader-read layout; handles go into `img` as soon as they exist, so
    /// an error part-way leaves them for the caller to destroy.
    fn r32_image(
        &self,
        img: &mut Img,
        what: &'static str,
        width: u32,
        height: u32,
        texels: &[f32],
    ) -> Result<(), VkError> {
        let vk = self.vk;
        let d = &vk.device;
        let max = vk.limits.max_image_dimension_2d;
        if width.max(height) > max {
            return Err(VkError::Limit {
                scheme: self.scheme.name.into(),
                what: "image texels along one side (maxImageDimension2D)",
                needed: width.max(height) as u64,
                max: max as u64,
                device: vk.name.clone(),
            });
        }
        let extent = vk::Extent3D {
            width,
            height,
            depth: 1,
        };
        img.image = unsafe {
            d.create_image(
                &vk::ImageCreateInfo::default()
                    .image_type(vk::ImageType::TYPE_2D)
                    .format(vk::Format::R32_SFLOAT)
                    .extent(extent)
                    .mip_levels(1)
                    .array_layers(1)
                    .samples(vk::SampleCountFlags::TYPE_1)
                    .tiling(vk::ImageTiling::OPTIMAL)
                    .usage(vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST)
                    .initial_layout(vk::ImageLayout::UNDEFINED),
                None,
            )
        }
        .map_err(call("vkCreateImage"))?;
        let req = unsafe { d.get_image_memory_requirements(img.image) };
        let ty = vk
            .memory_type(
                req.memory_type_bits,
                vk::MemoryPropertyFlags::DEVICE_LOCAL,
                what,
            )
            .or_else(|_| {
                vk.memory_type(req.memory_type_bits, vk::MemoryPropertyFlags::empty(), what)
            })?;
        img.memory = unsafe {
            d.allocate_memory(
                &vk::MemoryAllocateInfo::default()
                    .allocation_size(req.size)
                    .memory_type_index(ty),
                None,
            )
        }
        .map_err(call("vkAllocateMemory"))?;
        unsafe { d.bind_image_memory(img.image, img.memory, 0) }
            .map_err(call("vkBindImageMemory"))?;
        let bytes: Vec<u8> = texels.iter().flat_map(|w| w.to_le_bytes()).collect();
        let staging = vk.buffer(
            "image staging",
            bytes.len() as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
        )?;
        staging.write(&bytes);
        let range = vk::ImageSubresourceRange {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: 1,
        };
        let image = img.image;
        let copied = vk.submit(|d, cb| unsafe {
            let to_dst = vk::ImageMemoryBarrier::default()
                .old_layout(vk::ImageLayout::UNDEFINED)
                .new_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
                .dst_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .image(image)
                .subresource_range(range);
            d.cmd_pipeline_barrier(
                cb,
                vk::PipelineStageFlags::TOP_OF_PIPE,
                vk::PipelineStageFlags::TRANSFER,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[to_dst],
            );
            let region = vk::BufferImageCopy::default()
                .image_subresource(vk::ImageSubresourceLayers {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    mip_level: 0,
                    base_array_layer: 0,
                    layer_count: 1,
                })
                .image_extent(extent);
            d.cmd_copy_buffer_to_image(
                cb,
                staging.buffer,
                image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
            );
            let to_read = vk::ImageMemoryBarrier::default()
                .old_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
                .new_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)
                .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                .dst_access_mask(vk::AccessFlags::SHADER_READ)
                .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .image(image)
                .subresource_range(range);
            d.cmd_pipeline_barrier(
                cb,
                vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::ALL_COMMANDS,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[to_read],
            );
        });
        staging.destroy(d);
        copied?;
        img.view = unsafe {
            d.create_image_view(
                &vk::ImageViewCreateInfo::default()
                    .image(img.image)
                    .view_type(vk::ImageViewType::TYPE_2D)
                    .format(vk::Format::R32_SFLOAT)
                    .subresource_range(range),
                None,
            )
        }
        .map_err(call("vkCreateImageView"))?;
        Ok(())
    }

    /// The stencil table as an `R32_SFLOAT` image, its rows wrapped into
    /// column blocks (`kernels::table_texture`).
    pub(super) fn table(&mut self) -> Result<(), VkError> {
        let table = kernels::table_texture();
        let width = kernels::common::TABLE_TEXTURE_WIDTH;
        let height = kernels::common::TABLE_TEXTURE_HEIGHT;
        let mut img = Img::default();
        let made = self.r32_image(&mut img, "the stencil table", width, height, table);
        self.table_img = img;
        made?;
        let vk = self.vk;
        let d = &vk.device;
        self.sampler = unsafe {
            d.create_sampler(
                &vk::SamplerCreateInfo::default()
                    .mag_filter(vk::Filter::NEAREST)
                    .min_filter(vk::Filter::NEAREST)
                    .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
                    .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE),
                None,
            )
        }
        .map_err(call("vkCreateSampler"))?;
        Ok(())
    }

    /// The displacement map (`binding::DISPLACE_MAP`) as an `R32_SFLOAT` image; a 1×1
    /// zero map while displacement is off. Read with exact texel fetches.
    pub(super) fn map(&mut self) -> Result<(), VkError> {
        let m = self.displace_map.clone();
        let mut img = Img::default();
        let made = self.r32_image(
            &mut img,
            "the displacement map",
            m.width.max(1),
            m.height.max(1),
            &m.texels,
        );
        self.map_img = img;
        made
    }

    pub(super) fn write_buffer(&self, b: u32, buf: &Buf) {
        let info = [vk::DescriptorBufferInfo::default()
            .buffer(buf.buffer)
            .offset(0)
            .range(vk::WHOLE_SIZE)];
        let w = vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(b)
            .descriptor_type(self.descriptor_type(b))
            .buffer_info(&info);
        unsafe { self.vk.device.update_descriptor_sets(&[w], &[]) };
    }
}
