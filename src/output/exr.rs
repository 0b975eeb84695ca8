//! OpenEXR output: float32 channels R, G, B, X, Y, Z and spectral bands in the layout of
//! Fichet, Pacanowski & Wilkie (JCGT 2021): `S0.<λ>nm` emissive channels with a comma decimal
//! separator and the `spectralLayoutVersion` / `emissiveUnits` header attributes, so
//! colour-science's `read_spectral_image_Fichet2021` reads them.

use crate::config::ExrCompression;
use crate::error::Error;
use crate::film::Film;
use exr::block::{enumerate_ordered_header_block_indices, UncompressedBlock};
use exr::image::write::layers::{LayersWriter, WritableLayers};
use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Compression, Encoding, FlatSamples, Image,
    ImageAttributes, IntegerBounds, Layer, LayerAttributes, Text, WritableImage,
};
use rayon::prelude::*;
use std::path::Path;

/// Writes `film` to `path` (atomically), with extra text header attributes `extra`.
pub fn write(
    film: &Film,
    path: &Path,
    extra: &[(String, String)],
    compression: ExrCompression,
) -> Result<(), Error> {
    let size = (film.width as usize, film.height as usize);
    let channels: Vec<AnyChannel<FlatSamples>> = film
        .channels
        .iter()
        .map(|c| AnyChannel::new(c.name.as_str(), FlatSamples::F32(c.data.clone())))
        .chain(
            film.uint_channels
                .iter()
                .map(|c| AnyChannel::new(c.name.as_str(), FlatSamples::U32(c.data.clone()))),
        )
        .collect();
    let mut attrs = ImageAttributes::new(IntegerBounds::from_dimensions(size));
    let mut text = |k: &str, v: &str| -> Result<(), Error> {
        let key = Text::new_or_none(k)
            .ok_or_else(|| Error::Other(format!("EXR attribute name `{k}` is not ASCII")))?;
        // OpenEXR strings are bytes; ours are UTF-8 (so a scene named `場景.ron` is stored as
        // its UTF-8 bytes, which OpenImageIO and OpenEXR's own tools read back as UTF-8).
        let val = Text::from_slice_unchecked(v.as_bytes());
        attrs.other.insert(key, AttributeValue::Text(val));
        Ok(())
    };
    if !film.band_centers.is_empty() {
        text("spectralLayoutVersion", "1.0")?;
        text("emissiveUnits", "W.m^-2.sr^-1")?;
    }
    for (k, v) in film.header.iter().chain(extra) {
        text(k, v)?;
    }
    let layer = Layer::new(
        size,
        LayerAttributes::default(),
        Encoding {
            compression: match compression {
                ExrCompression::None => Compression::Uncompressed,
                ExrCompression::Rle => Compression::RLE,
                ExrCompression::Zip => Compression::ZIP16,
                ExrCompression::Piz => Compression::PIZ,
            },
            ..Encoding::SMALL_LOSSLESS
        },
        AnyChannels::sort(channels.into()),
    );
    let image = Image::empty(attrs).with_layer(layer);
    super::write_atomic(path, |tmp| {
        let mut bytes = encode(&image, compression).map_err(|e| e.to_string())?;
        // Same content, same bytes (the crate writes attributes in hash-map order).
        super::exr_header::sort_attributes(&mut bytes);
        std::fs::write(tmp, bytes).map_err(|e| e.to_string())
    })
}

/// The file's bytes: the crate's header and offset table, and the blocks compressed in
/// parallel, ZIP by `exr_zip` (a faster deflate level than the crate's), the rest by the
/// crate. The buffer is sized once, for the pixels uncompressed.
fn encode<L: for<'a> WritableLayers<'a>>(
    image: &Image<L>,
    compression: ExrCompression,
) -> exr::error::Result<Vec<u8>> {
    // Blocks compressed at once: enough to keep every thread busy, few enough that a large
    // film's compressed copy is not held whole beside the file's bytes.
    const BATCH: usize = 64;
    let headers = image.write().infer_meta_data();
    let layers = image.layer_data.create_writer(&headers);
    let raw: usize = headers
        .iter()
        .map(|h| h.channels.bytes_per_pixel * h.layer_size.area())
        .sum();
    let mut file = std::io::Cursor::new(Vec::with_capacity(raw + (1 << 16)));
    exr::block::write(&mut file, headers, true, |meta, writer| {
        let blocks: Vec<_> = enumerate_ordered_header_block_indices(&meta.headers).collect();
        for batch in blocks.chunks(BATCH) {
            let chunks: Vec<_> = batch
                .par_iter()
                .with_max_len(1)
                .map(|&(_, index)| {
                    let data = layers.extract_uncompressed_block(&meta.headers, index);
                    let block = UncompressedBlock { index, data };
                    match compression {
                        ExrCompression::Zip => Ok(super::exr_zip::chunk(block)),
                        _ => block.compress_to_chunk(&meta.headers),
                    }
                })
                .collect();
            for ((i, _), chunk) in batch.iter().zip(chunks) {
                exr::block::writer::ChunksWriter::write_chunk(writer, *i, chunk?)?;
            }
        }
        Ok(())
    })?;
    Ok(file.into_inner())
}
