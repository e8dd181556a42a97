//! The vtu reader's zlib blocks on arbitrary compressed bytes: the input's first 8 bytes give
//! the declared block size and point count, the rest is one zlib block in an appended array of
//! a fixed file. Never a panic; a block inflates only into the size its header declares.
#![no_main]

use filmsplat::io::{CloudFormat, ReadOptions, read_bytes};
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if data.len() < 8 {
        return;
    }
    let points = u32::from_le_bytes([data[0], data[1], data[2], data[3]]) % 4096;
    let declared = points * 12;
    let block = &data[8..];
    let mut b = format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt32\" compressor=\"vtkZLibDataCompressor\">\n\
         <UnstructuredGrid><Piece NumberOfPoints=\"{points}\" NumberOfCells=\"0\"><Points>\
         <DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/>\
         </Points></Piece></UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_"
    )
    .into_bytes();
    let last = u32::from_le_bytes([data[4], data[5], data[6], data[7]]) % (declared + 1);
    for v in [1u32, declared, last, block.len() as u32] {
        b.extend(v.to_le_bytes());
    }
    b.extend_from_slice(block);
    b.extend_from_slice(b"\n</AppendedData>\n</VTKFile>\n");
    if let Ok(cloud) = read_bytes(CloudFormat::VtkXml, &b, Path::new("fuzz.vtu"), &ReadOptions::default()).map(|(c, _)| c) {
        assert_eq!(cloud.positions.len() as u32, points);
    }
});
