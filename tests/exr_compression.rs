//! The EXR's compression (`film.exr_compression`, `--exr-compression`): every choice holds the
//! same pixels, bit for bit, float and integer channels alike, and says in its header which
//! compression it used; the default leaves serialized configs (and so a dataset's identity) as
//! they were before the option existed.

mod scratch;
use exr::prelude::*;
use std::path::Path;
use std::process::Command;

/// Every channel of the EXR at `path` as bits, sorted by name, and the file's compression.
fn read(path: &Path) -> (Vec<(String, Vec<u32>)>, Compression) {
    let img = read_all_flat_layers_from_file(path).unwrap();
    let layer = &img.layer_data[0];
    let mut channels: Vec<_> = layer
        .channel_data
        .list
        .iter()
        .map(|c| {
            let bits = match &c.sample_data {
                FlatSamples::F32(v) => v.iter().map(|x| x.to_bits()).collect(),
                FlatSamples::U32(v) => v.clone(),
                FlatSamples::F16(v) => v.iter().map(|x| x.to_bits() as u32).collect(),
            };
            (c.name.to_string(), bits)
        })
        .collect();
    channels.sort();
    (channels, layer.encoding.compression)
}

#[test]
fn every_compression_holds_the_same_pixels() {
    let dir = scratch::scratch("exrc", "pixels");
    let cornell =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell.ron"))
            .unwrap()
            .replace("width: 256, height: 256", "width: 24, height: 20");
    std::fs::write(dir.join("cornell.ron"), cornell).unwrap();
    let mut reference = None;
    for (flag, want) in [
        ("zip", Compression::ZIP16),
        ("none", Compression::Uncompressed),
        ("rle", Compression::RLE),
        ("piz", Compression::PIZ),
    ] {
        let out = dir.join(format!("{flag}.exr"));
        let o = Command::new(env!("CARGO_BIN_EXE_prism"))
            .current_dir(&*dir)
            .args([
                "render",
                "cornell.ron",
                "--spp",
                "2",
                "-q",
                "--exr-compression",
                flag,
            ])
            .args(["--aovs", "depth,normal,instance", "-o"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{flag}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let (channels, compression) = read(&out);
        assert_eq!(compression, want, "{flag}: the header's compression");
        // Float colour channels and the integer instance ids are both compared.
        assert!(channels.iter().any(|(n, _)| n == "R"));
        assert!(channels.iter().any(|(n, _)| n.starts_with("instance")));
        match &reference {
            None => reference = Some(channels),
            Some(r) => assert!(*r == channels, "{flag}: pixels differ from zip's"),
        }
    }
}

#[test]
fn the_default_is_zip_and_left_out_of_serialized_configs() {
    use prism::config::{ExrCompression, FilmConfig};
    let film = FilmConfig::default();
    assert_eq!(film.exr_compression, ExrCompression::Zip);
    let v = serde_json::to_value(&film).unwrap();
    assert!(v.get("exr_compression").is_none(), "{v}");
    let none = FilmConfig {
        exr_compression: ExrCompression::None,
        ..film
    };
    let v = serde_json::to_value(&none).unwrap();
    assert_eq!(v["exr_compression"], "None");
}
