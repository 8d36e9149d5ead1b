//! Parquet files written and read a column at a time, through the parquet
//! crate's own column API (arrow would hold a second copy of each column).
//! The fleet's tables and the Parquet session file are both written here.

use crate::source::Located;
use bytes::Bytes;
use parquet::data_type::{BoolType, ByteArray, ByteArrayType, DataType, Int32Type, Int64Type};
use parquet::file::properties::{WriterProperties, WriterPropertiesPtr};
use parquet::file::reader::RowGroupReader;
use parquet::file::writer::{SerializedFileWriter, SerializedRowGroupWriter};
use parquet::schema::parser::parse_message_type;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn failed(path: &Path, e: impl std::fmt::Display) -> Located {
    Located::file(path, format!("cannot write the Parquet file: {e}"))
}

/// A Parquet file being written at `part`, a row group at a time; errors
/// name `path`, the file it becomes.
pub struct Writer {
    path: PathBuf,
    w: SerializedFileWriter<File>,
    schema: parquet::schema::types::SchemaDescPtr,
}

impl Writer {
    /// Creates `part` (it must not exist) for a file of `schema`.
    pub fn create(
        path: &Path,
        part: &Path,
        schema: &str,
        props: WriterProperties,
    ) -> Result<Writer, Located> {
        let schema = Arc::new(parse_message_type(schema).map_err(|e| failed(path, e))?);
        let descr = Arc::new(parquet::schema::types::SchemaDescriptor::new(
            schema.clone(),
        ));
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(part)
            .map_err(|e| failed(part, e))?;
        let w = SerializedFileWriter::new(file, schema, Arc::new(props))
            .map_err(|e| failed(path, e))?;
        Ok(Writer {
            path: path.to_path_buf(),
            w,
            schema: descr,
        })
    }

    /// One row group, its columns written by `columns` in the schema's order.
    pub fn row_group(
        &mut self,
        columns: impl FnOnce(&mut Columns) -> parquet::errors::Result<()>,
    ) -> Result<(), Located> {
        let schema = self.schema.clone();
        let props = self.w.properties().clone();
        let mut rg = self.w.next_row_group().map_err(|e| failed(&self.path, e))?;
        let mut c = Columns {
            rg: &mut rg,
            schema,
            props,
            next: 0,
        };
        columns(&mut c).map_err(|e| failed(&self.path, e))?;
        rg.close().map_err(|e| failed(&self.path, e))?;
        Ok(())
    }

    /// Writes the footer; the file is then whole, and synced to disk.
    pub fn close(self) -> Result<(), Located> {
        let path = self.path.clone();
        let file = self.close_unsynced()?;
        file.sync_all().map_err(|e| failed(&path, e))
    }

    /// Writes the footer, leaving the sync to the caller (an export of
    /// thousands of files syncs them all at once).
    pub fn close_unsynced(self) -> Result<File, Located> {
        let path = self.path;
        self.w.into_inner().map_err(|e| failed(&path, e))
    }
}

/// The next columns of a row group, by type.
pub struct Columns<'a, 'b> {
    rg: &'a mut SerializedRowGroupWriter<'b, File>,
    schema: parquet::schema::types::SchemaDescPtr,
    props: WriterPropertiesPtr,
    next: usize,
}

impl Columns<'_, '_> {
    /// The next column, of Parquet type `P`; `None` is a missing value (the
    /// column is OPTIONAL).
    pub fn column<P: DataType>(
        &mut self,
        values: impl Iterator<Item = Option<P::T>>,
    ) -> parquet::errors::Result<()> {
        let (vals, defs) = split(values);
        let optional = self.schema.column(self.next).max_def_level() > 0;
        self.batch::<P>(&vals, optional.then_some(&defs[..]))
    }

    /// The next column's values, and its levels if it is OPTIONAL.
    fn batch<P: DataType>(
        &mut self,
        values: &[P::T],
        levels: Option<&[i16]>,
    ) -> parquet::errors::Result<()> {
        self.next += 1;
        let mut c = self.rg.next_column()?.expect("a column of the schema");
        c.typed::<P>().write_batch(values, levels, None)?;
        c.close()
    }

    /// A text column.
    pub fn strings<'s>(
        &mut self,
        values: impl Iterator<Item = Option<&'s str>>,
    ) -> parquet::errors::Result<()> {
        self.column::<ByteArrayType>(
            values.map(|v| v.map(|s| ByteArray::from(s.as_bytes().to_vec()))),
        )
    }

    /// A text column of few distinct values, each made once (`texts`) and
    /// shared by the rows that hold it (by index): a copy a row was most
    /// of an export's time.
    pub fn shared_strings(
        &mut self,
        texts: &[ByteArray],
        values: impl Iterator<Item = usize>,
    ) -> parquet::errors::Result<()> {
        self.column::<ByteArrayType>(values.map(|i| Some(texts[i].clone())))
    }

    /// A REQUIRED column whose rows are `dict[i]` for each `i` of
    /// `indices`, written as a dictionary page and one data page of the
    /// indices (RLE_DICTIONARY). The parquet crate's column writer hashes
    /// every value to find its place in the dictionary, where the caller
    /// knows it (that was a fifth of a fleet's export), and its encoders
    /// are public only with arrow built in: the two encodings are written
    /// here (`Plain`, `bit_packed`), and read back by the crate and by
    /// DuckDB in the tests.
    pub fn indexed<V: Plain>(
        &mut self,
        dict: &[V],
        indices: &[u32],
    ) -> parquet::errors::Result<()> {
        use parquet::basic::Encoding;
        use parquet::column::page::PageWriter;
        let descr = self.schema.column(self.next);
        self.next += 1;
        let codec = self.props.compression(descr.path());
        let pages = dictionary_pages(dict, indices, codec)?;
        let mut sink = parquet::file::writer::TrackedWrite::new(Vec::new());
        let mut specs = Vec::new();
        {
            let mut w = parquet::file::writer::SerializedPageWriter::new(&mut sink);
            for page in pages {
                specs.push(w.write_page(page)?);
            }
        }
        let metadata = parquet::file::metadata::ColumnChunkMetaData::builder(descr)
            .set_compression_codec(codec.into())
            .set_encodings(vec![
                Encoding::PLAIN,
                Encoding::RLE,
                Encoding::RLE_DICTIONARY,
            ])
            .set_total_compressed_size(specs.iter().map(|s| s.compressed_size as i64).sum())
            .set_total_uncompressed_size(specs.iter().map(|s| s.uncompressed_size as i64).sum())
            .set_num_values(indices.len() as i64)
            .set_dictionary_page_offset(Some(specs[0].offset as i64))
            .set_data_page_offset(specs[1].offset as i64)
            .build()?;
        let bytes: Bytes = sink.into_inner()?.into();
        self.rg.append_column(
            &bytes,
            parquet::column::writer::ColumnCloseResult {
                bytes_written: bytes.len() as u64,
                rows_written: indices.len() as u64,
                metadata,
                bloom_filter: None,
                column_index: None,
                offset_index: None,
            },
        )
    }

    /// A REQUIRED column of the values as they are, with no copy.
    pub fn values<P: DataType>(&mut self, values: &[P::T]) -> parquet::errors::Result<()> {
        self.batch::<P>(values, None)
    }

    /// An OPTIONAL column: the values present, and a level a row (1
    /// present, 0 missing).
    pub fn optional<P: DataType>(
        &mut self,
        values: &[P::T],
        levels: &[i16],
    ) -> parquet::errors::Result<()> {
        self.batch::<P>(values, Some(levels))
    }

    pub fn ints(
        &mut self,
        values: impl Iterator<Item = Option<i32>>,
    ) -> parquet::errors::Result<()> {
        self.column::<Int32Type>(values)
    }

    pub fn longs(
        &mut self,
        values: impl Iterator<Item = Option<i64>>,
    ) -> parquet::errors::Result<()> {
        self.column::<Int64Type>(values)
    }

    pub fn bools(&mut self, values: impl Iterator<Item = bool>) -> parquet::errors::Result<()> {
        self.column::<BoolType>(values.map(Some))
    }
}

/// The dictionary page (the values, PLAIN) and the data page (the
/// indices, bit-packed) of a column written by its indices, compressed
/// as its properties say.
fn dictionary_pages<V: Plain>(
    dict: &[V],
    indices: &[u32],
    codec: parquet::basic::Compression,
) -> parquet::errors::Result<[parquet::column::page::CompressedPage; 2]> {
    use parquet::basic::{Compression, Encoding};
    use parquet::column::page::{CompressedPage, Page};
    let pack = |plain: &[u8]| -> parquet::errors::Result<Bytes> {
        match codec {
            Compression::UNCOMPRESSED => Ok(Bytes::copy_from_slice(plain)),
            Compression::SNAPPY => snap::raw::Encoder::new()
                .compress_vec(plain)
                .map(Bytes::from)
                .map_err(|e| parquet::errors::ParquetError::External(Box::new(e))),
            other => Err(parquet::errors::ParquetError::NYI(format!(
                "{other} for a column written by its indices"
            ))),
        }
    };
    let mut dict_plain = Vec::new();
    for v in dict {
        v.plain(&mut dict_plain);
    }
    let width = bits(dict.len());
    let mut data_plain = vec![width];
    bit_packed(width, indices, &mut data_plain);
    Ok([
        CompressedPage::new(
            Page::DictionaryPage {
                buf: pack(&dict_plain)?,
                num_values: dict.len() as u32,
                encoding: Encoding::PLAIN,
                is_sorted: false,
            },
            dict_plain.len(),
        ),
        CompressedPage::new(
            Page::DataPage {
                buf: pack(&data_plain)?,
                num_values: indices.len() as u32,
                encoding: Encoding::RLE_DICTIONARY,
                def_level_encoding: Encoding::RLE,
                rep_level_encoding: Encoding::RLE,
                statistics: None,
            },
            data_plain.len(),
        ),
    ])
}

/// A dictionary's value as Parquet's PLAIN encoding writes it.
pub trait Plain {
    fn plain(&self, out: &mut Vec<u8>);
}

impl Plain for ByteArray {
    /// Its length (4 bytes, little-endian), then its bytes.
    fn plain(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&(self.len() as u32).to_le_bytes());
        out.extend_from_slice(self.data());
    }
}

impl Plain for i32 {
    fn plain(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

/// The bits an index into a dictionary of `n` values takes (at least one:
/// some readers take a width of 0 for a broken page).
fn bits(n: usize) -> u8 {
    (usize::BITS - n.saturating_sub(1).leading_zeros()).max(1) as u8
}

/// `values`, each under 2^`width`, as the bit-packed runs of Parquet's
/// RLE/bit-packing hybrid: a run's header is the number of its groups of
/// eight values, shifted left once and marked by a 1 (ULEB128), then the
/// values' bits packed from the lowest bit of the first byte on. A run
/// holds 64 groups at most, as the parquet crate writes them; the last
/// group is filled with zeros (the page says how many values it holds).
fn bit_packed(width: u8, values: &[u32], out: &mut Vec<u8>) {
    let w = usize::from(width);
    out.reserve(values.len().div_ceil(8) * w + values.len() / 256 + 2);
    let pack = packer(width);
    for run in values.chunks(64 * 8) {
        let groups = run.len().div_ceil(8);
        let mut header = (groups << 1) | 1;
        while header >= 0x80 {
            out.push((header as u8 & 0x7f) | 0x80);
            header >>= 7;
        }
        out.push(header as u8);
        let start = out.len();
        out.resize(start + groups * w, 0);
        let bytes = &mut out[start..];
        let (whole, last) = run.split_at(run.len() / 8 * 8);
        for (group, to) in whole.chunks_exact(8).zip(bytes.chunks_exact_mut(w)) {
            pack(group, to);
        }
        if !last.is_empty() {
            let mut padded = [0u32; 8];
            padded[..last.len()].copy_from_slice(last);
            pack(&padded, &mut bytes[(groups - 1) * w..]);
        }
    }
}

/// Packs eight values into `width` bytes: a function made for each width
/// up to 16 (every dictionary index a fleet's export writes), whose
/// shifts the compiler knows, which is most of what packing costs.
fn packer(width: u8) -> fn(&[u32], &mut [u8]) {
    match width {
        1 => pack_eight::<1>,
        2 => pack_eight::<2>,
        3 => pack_eight::<3>,
        4 => pack_eight::<4>,
        5 => pack_eight::<5>,
        6 => pack_eight::<6>,
        7 => pack_eight::<7>,
        8 => pack_eight::<8>,
        9 => pack_eight::<9>,
        10 => pack_eight::<10>,
        11 => pack_eight::<11>,
        12 => pack_eight::<12>,
        13 => pack_eight::<13>,
        14 => pack_eight::<14>,
        15 => pack_eight::<15>,
        16 => pack_eight::<16>,
        _ => pack_eight_wide,
    }
}

fn pack_eight<const W: u32>(group: &[u32], to: &mut [u8]) {
    let mut acc = 0u128;
    for (k, &v) in group.iter().enumerate().take(8) {
        acc |= u128::from(v) << (k as u32 * W);
    }
    to[..W as usize].copy_from_slice(&acc.to_le_bytes()[..W as usize]);
}

/// Eight values of more than 16 bits each, a byte at a time.
fn pack_eight_wide(group: &[u32], to: &mut [u8]) {
    let w = to.len().min(32) as u32;
    let (mut acc, mut held, mut at) = (0u64, 0u32, 0);
    for &v in group.iter().take(8) {
        acc |= u64::from(v) << held;
        held += w;
        while held >= 8 {
            to[at] = acc as u8;
            at += 1;
            acc >>= 8;
            held -= 8;
        }
    }
}

/// A column's values present, and the definition levels an OPTIONAL
/// column marks each row with (1 present, 0 missing).
fn split<T>(values: impl Iterator<Item = Option<T>>) -> (Vec<T>, Vec<i16>) {
    let n = values.size_hint().0;
    let mut vals = Vec::with_capacity(n);
    let mut defs = Vec::with_capacity(n);
    for v in values {
        defs.push(i16::from(v.is_some()));
        vals.extend(v);
    }
    (vals, defs)
}

/// Column `i` of a row group of `rows` rows, a value or `None` a row.
pub fn column<P: DataType>(
    rg: &dyn RowGroupReader,
    i: usize,
    rows: usize,
) -> parquet::errors::Result<Vec<Option<P::T>>> {
    let mut r = P::get_column_reader(rg.get_column_reader(i)?).ok_or_else(|| {
        parquet::errors::ParquetError::General(format!(
            "column {} is not of type {}",
            i + 1,
            P::get_physical_type()
        ))
    })?;
    let optional = rg.metadata().schema_descr().column(i).max_def_level() > 0;
    let (mut vals, mut defs) = (Vec::with_capacity(rows), Vec::with_capacity(rows));
    let mut read = 0;
    while read < rows {
        let (n, _, _) = r.read_records(rows - read, Some(&mut defs), None, &mut vals)?;
        if n == 0 {
            break;
        }
        read += n;
    }
    if read != rows || (optional && defs.len() != rows) {
        return Err(parquet::errors::ParquetError::General(format!(
            "column {} holds {read} of its row group's {rows} rows",
            i + 1
        )));
    }
    if !optional {
        return Ok(vals.into_iter().map(Some).collect());
    }
    let mut vals = vals.into_iter();
    defs.iter()
        .map(|&d| match d {
            0 => Ok(None),
            _ => vals.next().map(Some).ok_or_else(|| {
                parquet::errors::ParquetError::General(format!(
                    "column {} has fewer values than its levels say",
                    i + 1
                ))
            }),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use parquet::file::reader::{FileReader, SerializedFileReader};
    use proptest::prelude::*;

    /// Writes one row group of a text column and a number column by their
    /// indices, and reads both back with the parquet crate's own reader.
    fn round_trip(
        texts: &[String],
        numbers: &[i32],
        rows: &[(u32, u32)],
    ) -> (Vec<String>, Vec<i32>) {
        let dir = tempfile::tempdir().unwrap();
        let (path, part) = (dir.path().join("t.parquet"), dir.path().join("t.part"));
        let schema = "message t { REQUIRED BYTE_ARRAY text (UTF8); REQUIRED INT32 number; }";
        let props = WriterProperties::builder()
            .set_compression(parquet::basic::Compression::SNAPPY)
            .build();
        let mut w = Writer::create(&path, &part, schema, props).unwrap();
        let dict: Vec<ByteArray> = texts.iter().map(|t| ByteArray::from(t.as_str())).collect();
        let a: Vec<u32> = rows.iter().map(|r| r.0).collect();
        let b: Vec<u32> = rows.iter().map(|r| r.1).collect();
        w.row_group(|c| {
            c.indexed(&dict, &a)?;
            c.indexed(numbers, &b)
        })
        .unwrap();
        w.close().unwrap();
        let r = SerializedFileReader::new(File::open(&part).unwrap()).unwrap();
        let rg = r.get_row_group(0).unwrap();
        let text = column::<ByteArrayType>(&*rg, 0, rows.len()).unwrap();
        let number = column::<Int32Type>(&*rg, 1, rows.len()).unwrap();
        (
            text.into_iter()
                .map(|t| t.unwrap().as_utf8().unwrap().to_string())
                .collect(),
            number.into_iter().map(Option::unwrap).collect(),
        )
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        /// Every row reads back as the dictionary's value at its index,
        /// whatever the dictionary's size (so the width of the indices)
        /// and however many rows (whole runs of 512, groups of 8, a part).
        #[test]
        fn a_column_written_by_its_indices_reads_back_row_for_row(
            texts in 1usize..300,
            numbers in 1usize..70_000,
            rows in prop::collection::vec((any::<u32>(), any::<u32>()), 1..1_200),
        ) {
            let texts: Vec<String> = (0..texts).map(|i| format!("node {i}")).collect();
            let numbers: Vec<i32> = (0..numbers as i32).map(|i| i * 7 - 3).collect();
            let rows: Vec<(u32, u32)> = rows
                .into_iter()
                .map(|(a, b)| (a % texts.len() as u32, b % numbers.len() as u32))
                .collect();
            let (t, n) = round_trip(&texts, &numbers, &rows);
            let want_t: Vec<String> = rows.iter().map(|r| texts[r.0 as usize].clone()).collect();
            let want_n: Vec<i32> = rows.iter().map(|r| numbers[r.1 as usize]).collect();
            prop_assert_eq!(t, want_t);
            prop_assert_eq!(n, want_n);
        }
    }

    #[test]
    fn a_dictionary_of_one_value_still_takes_a_bit_an_index() {
        assert_eq!(bits(1), 1);
        assert_eq!(bits(2), 1);
        assert_eq!(bits(3), 2);
        assert_eq!(bits(256), 8);
        assert_eq!(bits(257), 9);
        let (t, n) = round_trip(&["only".into()], &[5], &[(0, 0); 1_000]);
        assert!(t.iter().all(|t| t == "only") && t.len() == 1_000);
        assert!(n.iter().all(|&n| n == 5));
    }
}
