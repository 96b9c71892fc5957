"""Ground motions: record files in and out (`files`) and generated record sets (`sets`)."""
