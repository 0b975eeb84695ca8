//! `output::write_atomic`, the one path every output file takes: a writer that fails half way
//! leaves an existing file byte for byte as it was and no temporary file behind; one that
//! succeeds replaces it whole.

use std::io::Write;

#[test]
fn a_failed_write_leaves_the_existing_file_untouched() {
    let dir = std::env::temp_dir().join(format!("prism-atomic-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("image.exr");
    let old: Vec<u8> = (0..10_000u32).map(|i| (i * 7 % 251) as u8).collect();
    std::fs::write(&path, &old).unwrap();

    let err = prism::output::write_atomic(&path, |tmp| {
        // Half a file, then a failure (a full disk, an encoder error).
        let mut f = std::fs::File::create(tmp).map_err(|e| e.to_string())?;
        f.write_all(&[0u8; 5000]).map_err(|e| e.to_string())?;
        Err("disk full".into())
    })
    .unwrap_err();
    assert!(err.to_string().contains("disk full"), "{err}");
    assert_eq!(
        std::fs::read(&path).unwrap(),
        old,
        "the old file was changed"
    );
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(
        left,
        vec![std::ffi::OsString::from("image.exr")],
        "{left:?}"
    );

    prism::output::write_atomic(&path, |tmp| {
        std::fs::write(tmp, b"new").map_err(|e| e.to_string())
    })
    .unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), b"new");
    std::fs::remove_dir_all(&dir).unwrap();
}
