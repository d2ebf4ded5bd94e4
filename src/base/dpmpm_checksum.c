/* Checksum of a dataset of a checkpoint, stored at write time and checked before a restart.
 * Used through module dpmpm_checksum, which documents the definition. Unsigned 64-bit
 * arithmetic is modulo 2^64 in C, which the FNV-1a multiplication needs. */
#include <stddef.h>
#include <stdint.h>

#define FNV1A64_OFFSET 14695039346656037925ULL
#define FNV1A64_PRIME 1099511628211ULL

/* FNV-1a (64 bit) of column j of ncols columns of width bytes each at a, the column's global
 * number first + j (8 bytes, least significant first) hashed before its bytes; the columns'
 * hashes combined by exclusive or, so that blocks of columns hashed apart (one per rank)
 * combine in any order to the hash of the whole. */
uint64_t dpmpm_checksum_columns(const void *a, int64_t width, int64_t ncols, int64_t first)
{
  const unsigned char *p = (const unsigned char *)a;
  uint64_t sum = 0, h, g;
  int64_t j, i;
  int b;
  for (j = 0; j < ncols; j++) {
    h = FNV1A64_OFFSET;
    g = (uint64_t)(first + j);
    for (b = 0; b < 8; b++) {
      h ^= (g >> (8 * b)) & 0xffu;
      h *= FNV1A64_PRIME;
    }
    for (i = 0; i < width; i++) {
      h ^= p[(size_t)j * (size_t)width + (size_t)i];
      h *= FNV1A64_PRIME;
    }
    sum ^= h;
  }
  return sum;
}
