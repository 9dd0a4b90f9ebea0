//! `sweep.parquet` (cargo feature `parquet`, off by default): the columns of `sweep.csv`,
//! typed. A column whose every cell is a whole number is INT64, one whose every cell is a
//! number is DOUBLE, any other is a UTF-8 string; an empty cell is null. One row group,
//! uncompressed (the feature builds parquet without its compression codecs and without
//! Arrow: see docs/sweeps.md for the build cost).

use std::sync::Arc;

use parquet::basic::{LogicalType, Repetition, Type as Physical};
use parquet::data_type::{ByteArray, ByteArrayType, DoubleType, Int64Type};
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::types::Type;

/// The type of one column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Int,
    Double,
    Text,
}

fn kind(cells: &[&str]) -> Kind {
    let present: Vec<&&str> = cells.iter().filter(|c| !c.is_empty()).collect();
    if !present.is_empty() && present.iter().all(|c| c.parse::<i64>().is_ok()) {
        Kind::Int
    } else if !present.is_empty() && present.iter().all(|c| c.parse::<f64>().is_ok()) {
        Kind::Double
    } else {
        Kind::Text
    }
}

/// The table `head`, `rows` (text cells, empty for none) as a Parquet file's bytes.
pub fn encode(head: &[String], rows: &[Vec<String>]) -> Result<Vec<u8>, String> {
    let err = |e: parquet::errors::ParquetError| e.to_string();
    let column = |k: usize| rows.iter().map(|r| r.get(k).map_or("", String::as_str)).collect::<Vec<_>>();
    let kinds: Vec<Kind> = (0..head.len()).map(|k| kind(&column(k))).collect();
    let fields = head
        .iter()
        .zip(&kinds)
        .map(|(name, kind)| {
            let (physical, logical) = match kind {
                Kind::Int => (Physical::INT64, None),
                Kind::Double => (Physical::DOUBLE, None),
                Kind::Text => (Physical::BYTE_ARRAY, Some(LogicalType::String)),
            };
            Type::primitive_type_builder(name, physical)
                .with_repetition(Repetition::OPTIONAL)
                .with_logical_type(logical)
                .build()
                .map(Arc::new)
                .map_err(err)
        })
        .collect::<Result<Vec<_>, String>>()?;
    let schema = Arc::new(Type::group_type_builder("sweep").with_fields(fields).build().map_err(err)?);
    let mut bytes = Vec::new();
    let mut writer =
        SerializedFileWriter::new(&mut bytes, schema, Arc::new(WriterProperties::builder().build())).map_err(err)?;
    let mut group = writer.next_row_group().map_err(err)?;
    let mut k = 0;
    while let Some(mut col) = group.next_column().map_err(err)? {
        let cells = column(k);
        let levels: Vec<i16> = cells.iter().map(|c| i16::from(!c.is_empty())).collect();
        let present = cells.iter().filter(|c| !c.is_empty());
        match kinds[k] {
            Kind::Int => {
                let v: Vec<i64> = present.map(|c| c.parse().unwrap_or_default()).collect();
                col.typed::<Int64Type>().write_batch(&v, Some(&levels), None).map_err(err)?;
            }
            Kind::Double => {
                let v: Vec<f64> = present.map(|c| c.parse().unwrap_or(f64::NAN)).collect();
                col.typed::<DoubleType>().write_batch(&v, Some(&levels), None).map_err(err)?;
            }
            Kind::Text => {
                let v: Vec<ByteArray> = present.map(|c| ByteArray::from(*c)).collect();
                col.typed::<ByteArrayType>().write_batch(&v, Some(&levels), None).map_err(err)?;
            }
        }
        col.close().map_err(err)?;
        k += 1;
    }
    group.close().map_err(err)?;
    writer.close().map_err(err)?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use parquet::file::reader::{FileReader, SerializedFileReader};
    use parquet::record::Field;

    #[test]
    fn a_table_round_trips_with_its_types_and_nulls() {
        let head: Vec<String> = ["index", "ship.mass", "status", "stopping_time"].map(String::from).to_vec();
        let rows = vec![
            vec!["0".into(), "500000".into(), "stopped".into(), "19.808".into()],
            vec!["1".into(), "750000.5".into(), "end time".into(), String::new()],
        ];
        let bytes = encode(&head, &rows).unwrap();
        let reader = SerializedFileReader::new(bytes::Bytes::from(bytes)).unwrap();
        assert_eq!(reader.metadata().file_metadata().num_rows(), 2);
        let read: Vec<Vec<(String, Field)>> = reader
            .get_row_iter(None)
            .unwrap()
            .map(|r| r.unwrap().get_column_iter().map(|(n, f)| (n.clone(), f.clone())).collect())
            .collect();
        assert_eq!(read[0][0], ("index".into(), Field::Long(0)));
        assert_eq!(read[1][1], ("ship.mass".into(), Field::Double(750000.5)));
        assert_eq!(read[1][2], ("status".into(), Field::Str("end time".into())));
        assert_eq!(read[0][3].1, Field::Double(19.808));
        assert_eq!(read[1][3].1, Field::Null);
    }
}
