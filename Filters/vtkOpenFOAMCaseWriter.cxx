// SPDX-License-Identifier: BSD-3-Clause
#include "vtkOpenFOAMCaseWriter.h"
#include "vtkARMeshKernels.h"
#include "vtkARInputChecks.h"
#include "vtkARSolverMesh.h"

#include "vtkAlgorithm.h"
#include "vtkAppendFilter.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataSetAttributes.h"
#include "vtkFieldData.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnstructuredGrid.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkErrorCode.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointDataToCellData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h> // getpid

vtkStandardNewMacro(vtkOpenFOAMCaseWriter);

namespace
{
namespace fs = std::filesystem;

const char* const StampName = ".vtkOpenFOAMCaseWriter";

// ============================================================================
// ---- Reading OpenFOAM dictionaries (ASCII): just enough to copy entries.
// A dictionary body is split into entries `key value;`, `key { ... }` and
// `#directive ...` lines; values stay text.
struct Entry
{
  std::string Key;
  std::string Value; // a block's inside, or the text before ';' (trimmed)
  bool Block = false;
  bool Directive = false;
};

std::string Trim(const std::string& s)
{
  const size_t b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos)
  {
    return "";
  }
  const size_t e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

/// The text with // and /* */ comments replaced by spaces (strings kept).
std::string StripComments(const std::string& text)
{
  std::string out;
  out.reserve(text.size());
  bool inString = false;
  for (size_t i = 0; i < text.size(); ++i)
  {
    const char c = text[i];
    if (inString)
    {
      out += c;
      if (c == '\\' && i + 1 < text.size())
      {
        out += text[++i];
      }
      else if (c == '"')
      {
        inString = false;
      }
    }
    else if (c == '"')
    {
      inString = true;
      out += c;
    }
    else if (c == '/' && i + 1 < text.size() && text[i + 1] == '/')
    {
      while (i < text.size() && text[i] != '\n')
      {
        ++i;
      }
      out += '\n';
    }
    else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*')
    {
      const size_t end = text.find("*/", i + 2);
      i = end == std::string::npos ? text.size() : end + 1;
      out += ' ';
    }
    else
    {
      out += c;
    }
  }
  return out;
}

/// Index of the bracket closing the one at s[open] (strings skipped), or npos.
size_t MatchClose(const std::string& s, size_t open)
{
  int depth = 0;
  bool inString = false;
  for (size_t i = open; i < s.size(); ++i)
  {
    const char c = s[i];
    if (inString)
    {
      if (c == '\\')
      {
        ++i;
      }
      else if (c == '"')
      {
        inString = false;
      }
      continue;
    }
    if (c == '"')
    {
      inString = true;
    }
    else if (c == '(' || c == '[' || c == '{')
    {
      ++depth;
    }
    else if (c == ')' || c == ']' || c == '}')
    {
      if (--depth == 0)
      {
        return i;
      }
    }
  }
  return std::string::npos;
}

bool SplitEntries(const std::string& s, std::vector<Entry>& entries, std::string& error)
{
  size_t i = 0;
  const size_t n = s.size();
  auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (true)
  {
    while (i < n && (space(s[i]) || s[i] == ';'))
    {
      ++i;
    }
    if (i >= n)
    {
      return true;
    }
    Entry entry;
    const size_t start = i;
    if (s[i] == '"')
    {
      const size_t end = s.find('"', i + 1);
      if (end == std::string::npos)
      {
        error = "an unterminated string";
        return false;
      }
      i = end + 1;
    }
    else
    {
      int depth = 0;
      while (i < n && (depth > 0 || (!space(s[i]) && s[i] != '{' && s[i] != ';')))
      {
        depth += s[i] == '(' ? 1 : s[i] == ')' ? -1 : 0;
        ++i;
      }
    }
    entry.Key = s.substr(start, i - start);
    if (entry.Key[0] == '#')
    {
      const size_t end = s.find('\n', i);
      entry.Directive = true;
      entry.Value = Trim(s.substr(i, end == std::string::npos ? std::string::npos : end - i));
      i = end == std::string::npos ? n : end;
      entries.push_back(entry);
      continue;
    }
    while (i < n && space(s[i]))
    {
      ++i;
    }
    if (i < n && s[i] == '{')
    {
      const size_t end = MatchClose(s, i);
      if (end == std::string::npos)
      {
        error = "the block of '" + entry.Key + "' is not closed";
        return false;
      }
      entry.Block = true;
      entry.Value = s.substr(i + 1, end - i - 1);
      i = end + 1;
      entries.push_back(entry);
      continue;
    }
    const size_t valueStart = i;
    while (i < n && s[i] != ';')
    {
      if (s[i] == '(' || s[i] == '[' || s[i] == '{' || s[i] == '"')
      {
        const size_t end = s[i] == '"' ? s.find('"', i + 1) : MatchClose(s, i);
        if (end == std::string::npos)
        {
          error = "a bracket in the value of '" + entry.Key + "' is not closed";
          return false;
        }
        i = end;
      }
      ++i;
    }
    if (i >= n)
    {
      error = "the entry '" + entry.Key + "' has no terminating ';'";
      return false;
    }
    entry.Value = Trim(s.substr(valueStart, i - valueStart));
    ++i;
    entries.push_back(entry);
  }
}

const Entry* Find(const std::vector<Entry>& entries, const std::string& key)
{
  for (const auto& e : entries)
  {
    if (e.Key == key)
    {
      return &e;
    }
  }
  return nullptr;
}

/// The first word of a value ("wall;" -> "wall").
std::string FirstWord(const std::string& value)
{
  std::istringstream in(value);
  std::string w;
  in >> w;
  return w;
}

bool ReadText(const fs::path& path, std::string& text)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
  {
    return false;
  }
  std::ostringstream s;
  s << in.rdbuf();
  text = s.str();
  return static_cast<bool>(in) || in.eof();
}

/// Empties the list of a field's `internalField nonuniform List<...> n
/// (...)` (the keyword at the start of a line): the writer needs to know
/// only that it is nonuniform, and the text passes below, char by char,
/// cost about a second per 1e6 cells and field.
void DropInternalFieldList(std::string& text)
{
  const std::string keyword = "internalField";
  for (size_t at = text.find(keyword); at != std::string::npos; at = text.find(keyword, at + 1))
  {
    const size_t line = text.find_last_not_of(" \t", at == 0 ? 0 : at - 1);
    if (at > 0 && line != std::string::npos && text[line] != '\n')
    {
      continue; // not at the start of a line ($internalField, a comment)
    }
    size_t i = text.find_first_not_of(" \t\r\n", at + keyword.size());
    if (i == std::string::npos || text.compare(i, 10, "nonuniform") != 0)
    {
      return;
    }
    const size_t open = text.find('(', i);
    const size_t semicolon = text.find(';', i);
    if (open == std::string::npos || (semicolon != std::string::npos && semicolon < open))
    {
      return;
    }
    int depth = 0;
    for (i = open; i < text.size(); ++i)
    {
      depth += text[i] == '(' ? 1 : text[i] == ')' ? -1 : 0;
      if (depth == 0)
      {
        text.erase(open + 1, i - open - 1);
        return;
      }
    }
    return; // not closed: the parser below says so
  }
}

/// A dictionary file: its entries, the FoamFile header's entries. With
/// `field`, a nonuniform internalField's list is not read (its text is
/// `nonuniform List<...> n()`).
bool ReadDictionary(const fs::path& path, std::vector<Entry>& entries,
  std::vector<Entry>& header, std::string& error, bool field = false)
{
  std::string text;
  if (!ReadText(path, text))
  {
    error = "cannot read '" + path.string() + "'";
    return false;
  }
  if (field)
  {
    DropInternalFieldList(text);
  }
  std::string why;
  if (!SplitEntries(StripComments(text), entries, why))
  {
    error = "'" + path.string() + "' is not a readable OpenFOAM dictionary (" + why + ")";
    return false;
  }
  const Entry* h = Find(entries, "FoamFile");
  if (!h || !h->Block || !SplitEntries(h->Value, header, why))
  {
    error = "'" + path.string() + "' has no FoamFile header";
    return false;
  }
  return true;
}

// ============================================================================
// ---- Numbers as text.
/// Shortest text that reads back as the same double; for a value that is
/// exactly a float (`single` data, or any value a float holds exactly, as
/// the OpenFOAM reader's floats carried through double arrays are), the
/// shortest text that reads back as that float: the source's own digits.
void AppendNumber(std::string& s, double v, bool single)
{
  // std::to_chars without a format: the shortest text that reads back as
  // the same value, in one call (not %.*g at rising precisions with
  // snprintf, each read back with strtod)
  char buffer[64];
  const std::to_chars_result r = (single || static_cast<double>(static_cast<float>(v)) == v)
    ? std::to_chars(buffer, buffer + sizeof(buffer), static_cast<float>(v))
    : std::to_chars(buffer, buffer + sizeof(buffer), v);
  s.append(buffer, r.ptr);
}

/// An integer as text (std::to_chars), appended.
void AppendLabel(std::string& s, long long v)
{
  char buffer[24];
  const std::to_chars_result r = std::to_chars(buffer, buffer + sizeof(buffer), v);
  s.append(buffer, r.ptr);
}

/// Integers as text, one per line (a labelList's body).
template <typename Labels>
void AppendLabelLines(std::string& s, const Labels& labels)
{
  for (const auto v : labels)
  {
    AppendLabel(s, v);
    s += '\n';
  }
}

/// A label / scalar as OpenFOAM's binary format holds it (32-bit labels,
/// 64-bit scalars, this machine's byte order), appended.
void AppendRawLabel(std::string& s, vtkIdType v)
{
  const std::int32_t label = static_cast<std::int32_t>(v);
  s.append(reinterpret_cast<const char*>(&label), sizeof(label));
}

void AppendRawScalar(std::string& s, double v)
{
  s.append(reinterpret_cast<const char*>(&v), sizeof(v));
}

/// The `arch` entry of a binary file's header.
std::string Architecture()
{
  const std::uint16_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return std::string(first == 1 ? "LSB" : "MSB") + ";label=32;scalar=64";
}

// ============================================================================
// ---- Big lists: formatted in parallel, written in order.
/// Writes items [0, n) to `out`, `append(s, i)` appending item i's bytes
/// (text or raw) to `s`: chunks of items are formatted in parallel
/// (vtkSMPTools, a batch of chunks at a time so that memory stays bounded)
/// and written in order, so the file is the serial loop's, byte for byte.
template <typename Append>
void WriteItems(std::ostream& out, vtkIdType n, const Append& append)
{
  const vtkIdType chunk = 8192;
  const vtkIdType batch = 128; // chunks in memory at once (about 1e6 items)
  const vtkIdType nChunks = (n + chunk - 1) / chunk;
  std::vector<std::string> texts(static_cast<size_t>(std::min(batch, nChunks)));
  for (vtkIdType b = 0; b < nChunks && out; b += batch)
  {
    const vtkIdType e = std::min(nChunks, b + batch);
    vtkARMeshKernels::Threaded([&]() {
      vtkSMPTools::For(b, e, 1, [&](vtkIdType first, vtkIdType last) {
        for (vtkIdType k = first; k < last; ++k)
        {
          std::string& text = texts[static_cast<size_t>(k - b)];
          text.clear();
          const vtkIdType end = std::min(n, (k + 1) * chunk);
          for (vtkIdType i = k * chunk; i < end; ++i)
          {
            append(text, i);
          }
        }
      });
    });
    for (vtkIdType k = b; k < e; ++k)
    {
      const std::string& text = texts[static_cast<size_t>(k - b)];
      out.write(text.data(), static_cast<std::streamsize>(text.size()));
    }
  }
}

/// A List of n items as OpenFOAM writes it: ASCII `n\n(\n` one item per
/// line `)\n` (`append` ends each item with its newline); binary `n\n(`
/// the raw items in one block `)\n`, or `n` alone when empty.
template <typename Append>
void WriteList(std::ostream& out, bool binary, vtkIdType n, const Append& append)
{
  out << n << '\n';
  if (binary && n == 0)
  {
    return;
  }
  out << (binary ? "(" : "(\n");
  WriteItems(out, n, append);
  out << ")\n";
}

/// Writes `path`: `body` streams the content. False with `error` when the
/// file cannot be opened or written.
bool WriteFile(const fs::path& path, const std::function<void(std::ostream&)>& body, std::string& error)
{
  std::ofstream out(path, std::ios::out | std::ios::trunc | std::ios::binary);
  if (!out)
  {
    error = "cannot open '" + path.string() + "' for writing";
    return false;
  }
  body(out);
  out.close();
  if (!out)
  {
    error = "writing '" + path.string() + "' failed (disk full?)";
    return false;
  }
  return true;
}

bool IsNumber(const std::string& text, double* value = nullptr)
{
  if (text.empty())
  {
    return false;
  }
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(v))
  {
    return false;
  }
  if (value)
  {
    *value = v;
  }
  return true;
}

std::string Header(const std::string& cls, const std::string& location,
  const std::string& object, const std::string& note = "", bool binary = false)
{
  std::string s = "/*--------------------------------*- C++ -*----------------------------------*\\\n"
                  "  Written by AdaptiveRedistribution's vtkOpenFOAMCaseWriter\n"
                  "\\*---------------------------------------------------------------------------*/\n"
                  "FoamFile\n{\n    version     2.0;\n";
  s += binary ? "    format      binary;\n    arch        \"" + Architecture() + "\";\n"
              : "    format      ascii;\n";
  s += "    class       " + cls + ";\n";
  if (!note.empty())
  {
    s += "    note        \"" + note + "\";\n";
  }
  s += "    location    \"" + location + "\";\n";
  s += "    object      " + object + ";\n}\n\n";
  return s;
}

/// Patch types whose fields must have the same type.
bool IsConstraintType(const std::string& type)
{
  static const std::set<std::string> constraint = { "empty", "wedge", "symmetryPlane",
    "symmetry", "cyclic", "cyclicAMI", "cyclicACMI", "cyclicSlip", "processor", "nonConformalCyclic" };
  return constraint.count(type) > 0;
}

/// Components of an OpenFOAM List<type>.
int ComponentsOf(const std::string& type)
{
  if (type == "vector")
  {
    return 3;
  }
  if (type == "symmTensor")
  {
    return 6;
  }
  if (type == "tensor")
  {
    return 9;
  }
  return 1; // scalar, sphericalTensor
}

// ============================================================================
// ---- The source case.
struct SourcePatch
{
  std::string Type = "patch";
  std::vector<Entry> Entries; // all but nFaces and startFace
  std::vector<std::string> Groups;
};

struct SourceField
{
  std::string Name;
  std::string Class; // volScalarField or volVectorField
  std::string Dimensions;
  std::string InternalField;
  std::vector<Entry> TopLevel;   // other top-level entries, copied
  std::vector<Entry> Boundary;   // boundaryField entries
};

/// The words of an OpenFOAM word list ("List<word> 2(wall viscous)", "(wall)").
std::vector<std::string> WordList(const std::string& value)
{
  std::vector<std::string> words;
  const size_t open = value.find('(');
  const size_t close = value.rfind(')');
  if (open == std::string::npos || close == std::string::npos || close < open)
  {
    return words;
  }
  std::istringstream in(value.substr(open + 1, close - open - 1));
  std::string w;
  while (in >> w)
  {
    words.push_back(w);
  }
  return words;
}

// ============================================================================
// ---- One write: the options, the mesh and the fields, passes over them.
struct Field
{
  std::string Name;
  int Components = 1;
  std::vector<double> Values; // per model cell
  bool Single = false;
  const SourceField* Source = nullptr;
  std::string UniformValue; // non-empty: written uniform (no input array)
};

struct CaseJob
{
  vtkOpenFOAMCaseWriter* Writer = nullptr;
  vtkARSolverMesh Mesh;
  bool Binary = false; // the polyMesh and field files in OpenFOAM's binary format
  std::string StartTime;
  fs::path Source;     // empty: no source case
  std::string SourceTime;
  fs::path SourceTimeDir;
  std::string Warnings;

  std::map<std::string, SourcePatch> SourcePatches;
  std::vector<SourceField> SourceFields;
  std::vector<std::string> PatchTypes; // per mesh patch
  std::vector<std::vector<Entry>> PatchEntries; // per mesh patch, for boundary
  std::vector<std::vector<std::string>> PatchGroups;
  std::vector<Field> Fields;

  // ---- Pass 1: the source case's boundary, time directory and fields.
  bool ReadSource(std::string& error)
  {
    const fs::path boundary = this->Source / "constant" / "polyMesh" / "boundary";
    if (!fs::is_regular_file(boundary))
    {
      error = "the SourceCase '" + this->Source.string() + "' has no constant/polyMesh/boundary";
      return false;
    }
    std::string text;
    if (!ReadText(boundary, text))
    {
      error = "cannot read '" + boundary.string() + "'";
      return false;
    }
    text = StripComments(text);
    std::vector<Entry> top;
    const size_t header = text.find("FoamFile");
    const size_t headerOpen = header == std::string::npos ? header : text.find('{', header);
    const size_t headerClose =
      headerOpen == std::string::npos ? headerOpen : MatchClose(text, headerOpen);
    const size_t open = headerClose == std::string::npos ? headerClose : text.find('(', headerClose);
    const size_t close = open == std::string::npos ? open : MatchClose(text, open);
    std::string why;
    std::vector<Entry> patches;
    if (close == std::string::npos || !SplitEntries(text.substr(open + 1, close - open - 1), patches, why))
    {
      error = "'" + boundary.string() + "' is not a readable polyMesh boundary file" +
        (why.empty() ? "" : " (" + why + ")");
      return false;
    }
    for (const auto& p : patches)
    {
      std::vector<Entry> inner;
      if (!p.Block || !SplitEntries(p.Value, inner, why))
      {
        error = "patch '" + p.Key + "' of '" + boundary.string() + "' is malformed";
        return false;
      }
      SourcePatch sp;
      for (const auto& e : inner)
      {
        if (e.Key == "nFaces" || e.Key == "startFace")
        {
          continue;
        }
        if (e.Key == "type")
        {
          sp.Type = FirstWord(e.Value);
        }
        if (e.Key == "inGroups")
        {
          sp.Groups = WordList(e.Value);
        }
        sp.Entries.push_back(e);
      }
      this->SourcePatches[p.Key] = sp;
    }
    if (!fs::is_regular_file(this->Source / "system" / "controlDict"))
    {
      error = "the SourceCase '" + this->Source.string() + "' has no system/controlDict";
      return false;
    }

    // The time directory.
    if (this->SourceTime.empty() || this->SourceTime == "latest")
    {
      double latest = -HUGE_VAL;
      for (const auto& d : fs::directory_iterator(this->Source))
      {
        double t = 0.0;
        if (d.is_directory() && IsNumber(d.path().filename().string(), &t) && t > latest)
        {
          latest = t;
          this->SourceTimeDir = d.path();
        }
      }
      if (this->SourceTimeDir.empty())
      {
        this->Warnings += "the SourceCase has no time directory: no field is written\n";
        return true;
      }
    }
    else
    {
      this->SourceTimeDir = this->Source / this->SourceTime;
      if (!fs::is_directory(this->SourceTimeDir))
      {
        error = "the SourceCase has no time directory '" + this->SourceTime + "' (SourceTime)";
        return false;
      }
    }
    std::vector<fs::path> files;
    for (const auto& f : fs::directory_iterator(this->SourceTimeDir))
    {
      if (f.is_regular_file() && f.path().filename().string()[0] != '.')
      {
        files.push_back(f.path());
      }
    }
    std::sort(files.begin(), files.end());
    for (const auto& file : files)
    {
      const std::string name = file.filename().string();
      if (file.extension() == ".gz")
      {
        error = "the source field '" + file.string() +
          "' is compressed: gunzip the SourceCase's fields (or run it with writeCompression off)";
        return false;
      }
      std::vector<Entry> entries, head;
      if (!ReadDictionary(file, entries, head, error, /*field=*/true))
      {
        return false;
      }
      const Entry* cls = Find(head, "class");
      const Entry* format = Find(head, "format");
      const std::string c = cls ? FirstWord(cls->Value) : "";
      if (c != "volScalarField" && c != "volVectorField")
      {
        if (c.rfind("vol", 0) == 0)
        {
          this->Warnings += "source field '" + name + "' is a " + c +
            "; only volScalarField and volVectorField are written\n";
        }
        continue;
      }
      if (format && FirstWord(format->Value) != "ascii")
      {
        error = "the source field '" + file.string() +
          "' is in binary format: run foamFormatConvert on the SourceCase (writeFormat ascii)";
        return false;
      }
      SourceField field;
      field.Name = name;
      field.Class = c;
      const Entry* dims = Find(entries, "dimensions");
      const Entry* internal = Find(entries, "internalField");
      const Entry* bf = Find(entries, "boundaryField");
      std::string why;
      if (!dims || !internal || !bf || !bf->Block || !SplitEntries(bf->Value, field.Boundary, why))
      {
        error = "the source field '" + file.string() +
          "' has no dimensions, internalField or boundaryField (or a malformed one" +
          (why.empty() ? "" : ": " + why) + ")";
        return false;
      }
      field.Dimensions = dims->Value;
      field.InternalField = internal->Value;
      for (const auto& e : entries)
      {
        if (e.Key != "FoamFile" && e.Key != "dimensions" && e.Key != "internalField" &&
          e.Key != "boundaryField")
        {
          field.TopLevel.push_back(e);
        }
      }
      this->SourceFields.push_back(std::move(field));
    }
    return true;
  }

  // ---- Pass 2: patch types (source, or `empty` for a one-cell-deep mesh).
  void PatchTypesFromSource()
  {
    const size_t nPatches = this->Mesh.Patches.size();
    this->PatchTypes.assign(nPatches, "patch");
    this->PatchEntries.assign(nPatches, {});
    this->PatchGroups.assign(nPatches, {});
    if (!this->Source.empty())
    {
      for (size_t p = 0; p < nPatches; ++p)
      {
        auto it = this->SourcePatches.find(this->Mesh.Patches[p].Name);
        if (it == this->SourcePatches.end())
        {
          this->Warnings += "patch '" + this->Mesh.Patches[p].Name +
            "' is not in the SourceCase's boundary: written as type patch\n";
          continue;
        }
        this->PatchTypes[p] = it->second.Type;
        this->PatchEntries[p] = it->second.Entries;
        this->PatchGroups[p] = it->second.Groups;
      }
      return;
    }
    // One cell deep: every point on one of two parallel planes. The normal
    // of a patch's first face is tried as the planes' normal.
    const vtkARSolverMesh& m = this->Mesh;
    double lo[3] = { HUGE_VAL, HUGE_VAL, HUGE_VAL }, hi[3] = { -HUGE_VAL, -HUGE_VAL, -HUGE_VAL };
    for (vtkIdType i = 0; i < m.GetNumberOfPoints(); ++i)
    {
      for (int k = 0; k < 3; ++k)
      {
        lo[k] = std::min(lo[k], m.Points[3 * i + k]);
        hi[k] = std::max(hi[k], m.Points[3 * i + k]);
      }
    }
    const double diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
      (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    const double tolerance = 1e-6 * diagonal;
    auto dot = [&](const double n[3], vtkIdType i) {
      return n[0] * m.Points[3 * i] + n[1] * m.Points[3 * i + 1] + n[2] * m.Points[3 * i + 2];
    };
    for (const auto& patch : m.Patches)
    {
      // Newell normal of the first face.
      double n[3] = { 0, 0, 0 };
      const vtkIdType b = patch.Offsets[0], e = patch.Offsets[1];
      for (vtkIdType i = b; i < e; ++i)
      {
        const double* p = &m.Points[3 * patch.Connectivity[i]];
        const double* q = &m.Points[3 * patch.Connectivity[i + 1 < e ? i + 1 : b]];
        n[0] += (p[1] - q[1]) * (p[2] + q[2]);
        n[1] += (p[2] - q[2]) * (p[0] + q[0]);
        n[2] += (p[0] - q[0]) * (p[1] + q[1]);
      }
      const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (!(length > 0.0))
      {
        continue;
      }
      for (double& v : n)
      {
        v /= length;
      }
      double smin = HUGE_VAL, smax = -HUGE_VAL;
      for (vtkIdType i = 0; i < m.GetNumberOfPoints(); ++i)
      {
        smin = std::min(smin, dot(n, i));
        smax = std::max(smax, dot(n, i));
      }
      if (!(smax - smin > 10.0 * tolerance))
      {
        continue;
      }
      auto level = [&](vtkIdType i) {
        const double s = dot(n, i);
        return std::abs(s - smin) <= tolerance ? 0 : std::abs(s - smax) <= tolerance ? 1 : -1;
      };
      bool twoPlanes = true;
      for (vtkIdType i = 0; i < m.GetNumberOfPoints() && twoPlanes; ++i)
      {
        twoPlanes = level(i) >= 0;
      }
      if (!twoPlanes)
      {
        continue;
      }
      for (size_t p = 0; p < m.Patches.size(); ++p)
      {
        const auto& q = m.Patches[p];
        bool inPlanes = true;
        for (vtkIdType f = 0; f < q.GetNumberOfFaces() && inPlanes; ++f)
        {
          const int first = level(q.Connectivity[q.Offsets[f]]);
          for (vtkIdType i = q.Offsets[f]; i < q.Offsets[f + 1] && inPlanes; ++i)
          {
            inPlanes = level(q.Connectivity[i]) == first;
          }
        }
        if (inPlanes)
        {
          this->PatchTypes[p] = "empty";
        }
      }
      return;
    }
  }

  // ---- Pass 3: the fields' cell values from the input's arrays.
  bool CollectFields(std::string& error)
  {
    vtkDataSet* volume = this->Mesh.Volume;
    vtkSmartPointer<vtkDataSet> averaged; // point data averaged to cells, on demand
    auto cellArray = [&](const std::string& name) -> std::pair<vtkDataArray*, bool> {
      if (auto* a = vtkDataArray::SafeDownCast(volume->GetCellData()->GetAbstractArray(name.c_str())))
      {
        return { a, true };
      }
      auto* pointArray =
        vtkDataArray::SafeDownCast(volume->GetPointData()->GetAbstractArray(name.c_str()));
      if (!pointArray)
      {
        return { nullptr, false };
      }
      if (!averaged)
      {
        auto copy = vtkSmartPointer<vtkDataSet>::Take(volume->NewInstance());
        copy->ShallowCopy(volume);
        copy->GetCellData()->Initialize();
        vtkNew<vtkPointDataToCellData> toCells;
        toCells->SetInputData(copy);
        toCells->SetProcessAllArrays(true);
        toCells->SetPassPointData(false);
        toCells->Update();
        averaged = vtkDataSet::SafeDownCast(toCells->GetOutputDataObject(0));
      }
      return { averaged ? averaged->GetCellData()->GetArray(name.c_str()) : nullptr, false };
    };
    auto fill = [&](Field& field, vtkDataArray* array) {
      const vtkIdType nCells = this->Mesh.GetNumberOfCells();
      field.Values.resize(static_cast<size_t>(nCells * field.Components));
      field.Single = array->GetDataType() == VTK_FLOAT;
      for (vtkIdType c = 0; c < nCells; ++c)
      {
        for (int k = 0; k < field.Components; ++k)
        {
          const double v = array->GetComponent(this->Mesh.InputCellIds[c], k);
          if (!std::isfinite(v))
          {
            error = "the array '" + field.Name + "' has a NaN or Inf value (cell " +
              std::to_string(this->Mesh.InputCellIds[c]) + ")";
            return false;
          }
          field.Values[static_cast<size_t>(c * field.Components + k)] = v;
        }
      }
      return true;
    };

    if (!this->Source.empty())
    {
      for (const auto& source : this->SourceFields)
      {
        Field field;
        field.Name = source.Name;
        field.Components = source.Class == "volVectorField" ? 3 : 1;
        field.Source = &source;
        vtkDataArray* array = cellArray(source.Name).first;
        if (!array)
        {
          if (FirstWord(source.InternalField) == "uniform")
          {
            field.UniformValue = source.InternalField;
            this->Warnings += "the input has no array '" + source.Name +
              "': it is written uniform, as the source's internalField\n";
            this->Fields.push_back(std::move(field));
          }
          else
          {
            this->Warnings += "the input has no array '" + source.Name +
              "' (a field of the SourceCase): it is not written\n";
          }
          continue;
        }
        if (array->GetNumberOfComponents() != field.Components)
        {
          error = "the array '" + source.Name + "' has " +
            std::to_string(array->GetNumberOfComponents()) + " components, but the source's '" +
            source.Name + "' is a " + source.Class;
          return false;
        }
        if (!fill(field, array))
        {
          return false;
        }
        this->Fields.push_back(std::move(field));
      }
      return true;
    }

    // No source case: every 1- and 3-component numeric array, cell arrays first.
    static const std::set<std::string> bookkeeping = { "PatchId", "vtkGhostType",
      "vtkOriginalCellIds", "vtkOriginalPointIds" };
    std::set<std::string> written;
    for (vtkDataSetAttributes* data :
      { static_cast<vtkDataSetAttributes*>(volume->GetCellData()),
        static_cast<vtkDataSetAttributes*>(volume->GetPointData()) })
    {
      for (int i = 0; i < data->GetNumberOfArrays(); ++i)
      {
        vtkDataArray* a = data->GetArray(i);
        if (!a || !a->GetName() || bookkeeping.count(a->GetName()) ||
          (a->GetNumberOfComponents() != 1 && a->GetNumberOfComponents() != 3))
        {
          continue;
        }
        const std::string raw = a->GetName();
        std::string name;
        for (char ch : raw)
        {
          name += (std::isspace(static_cast<unsigned char>(ch)) || ch == '"' || ch == ';' ||
                    ch == '{' || ch == '}' || ch == '(' || ch == ')' || ch == '/' || ch == '\\')
            ? '_'
            : ch;
        }
        if (name.empty() || written.count(name))
        {
          continue; // a point array of the same name as a cell array
        }
        written.insert(name);
        if (name != raw)
        {
          this->Warnings += "array '" + raw + "' is written as field '" + name + "'\n";
        }
        Field field;
        field.Name = name;
        field.Components = a->GetNumberOfComponents();
        vtkDataArray* values = cellArray(raw).first;
        if (!values)
        {
          continue;
        }
        if (!fill(field, values))
        {
          return false;
        }
        this->Fields.push_back(std::move(field));
      }
    }
    return true;
  }

  // ---- Writing.
  static bool Save(const fs::path& path, const std::string& text, std::string& error)
  {
    std::ofstream out(path, std::ios::out | std::ios::trunc | std::ios::binary);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out)
    {
      error = "writing '" + path.string() + "' failed (disk full?)";
      return false;
    }
    return true;
  }

  /// A cell's value: ASCII text (a vector in brackets), or binary raw doubles.
  void AppendValue(std::string& s, const Field& field, vtkIdType cell) const
  {
    const double* v = field.Values.data() + cell * field.Components;
    if (this->Binary)
    {
      for (int k = 0; k < field.Components; ++k)
      {
        AppendRawScalar(s, v[k]);
      }
      return;
    }
    if (field.Components == 1)
    {
      AppendNumber(s, v[0], field.Single);
      return;
    }
    s += '(';
    for (int k = 0; k < field.Components; ++k)
    {
      if (k)
      {
        s += ' ';
      }
      AppendNumber(s, v[k], field.Single);
    }
    s += ')';
  }

  /// `nonuniform List<...> n (values of the cells next to the patch's faces)`.
  std::string FaceValues(const Field& field, size_t patch) const
  {
    const auto& p = this->Mesh.Patches[patch];
    std::string s = field.Components == 1 ? "nonuniform List<scalar> " : "nonuniform List<vector> ";
    s += std::to_string(p.GetNumberOfFaces());
    if (p.GetNumberOfFaces() == 0)
    {
      return s + (this->Binary ? "" : "()");
    }
    s += this->Binary ? "(" : "\n(\n";
    for (vtkIdType f = 0; f < p.GetNumberOfFaces(); ++f)
    {
      this->AppendValue(s, field, p.Cells[f]);
      s += this->Binary ? "" : "\n";
    }
    return s + (this->Binary ? ")" : ")\n");
  }

  /// `uniform <mean>` of a `nonuniform List<type> n(...)` value.
  static bool MeanOfList(const std::string& value, std::string& uniform)
  {
    const size_t lt = value.find('<'), gt = value.find('>');
    if (lt == std::string::npos || gt == std::string::npos || gt < lt)
    {
      return false;
    }
    const int nc = ComponentsOf(Trim(value.substr(lt + 1, gt - lt - 1)));
    size_t open = value.find_first_of("({", gt);
    if (open == std::string::npos)
    {
      return false;
    }
    std::string inside = value.substr(open + 1);
    std::replace_if(inside.begin(), inside.end(), [](char c) { return c == '(' || c == ')' || c == '{' || c == '}'; }, ' ');
    std::istringstream in(inside);
    std::vector<double> sum(static_cast<size_t>(nc), 0.0);
    size_t count = 0;
    double v;
    while (in >> v)
    {
      sum[count % nc] += v;
      ++count;
    }
    const size_t n = count / nc;
    std::string s = "uniform ";
    s += nc > 1 ? "(" : "";
    for (int k = 0; k < nc; ++k)
    {
      if (k)
      {
        s += ' ';
      }
      AppendNumber(s, n ? sum[k] / static_cast<double>(n) : 0.0, false);
    }
    s += nc > 1 ? ")" : "";
    uniform = s;
    return true;
  }

  /// The boundaryField entry of `field` for mesh patch `p` (its inside).
  bool PatchEntry(const Field& field, size_t p, std::string& body, std::string& error) const
  {
    const std::string& name = this->Mesh.Patches[p].Name;
    const std::string& type = this->PatchTypes[p];
    const Entry* source = nullptr;
    if (field.Source)
    {
      const auto& entries = field.Source->Boundary;
      source = Find(entries, name);
      if (!source)
      {
        source = Find(entries, "\"" + name + "\"");
      }
      for (size_t g = 0; !source && g < this->PatchGroups[p].size(); ++g)
      {
        source = Find(entries, this->PatchGroups[p][g]);
      }
      for (size_t e = entries.size(); !source && e-- > 0;)
      {
        const std::string& key = entries[e].Key;
        if (key.size() > 2 && key.front() == '"' && key.back() == '"')
        {
          try
          {
            if (std::regex_match(name, std::regex(key.substr(1, key.size() - 2), std::regex::extended)))
            {
              source = &entries[e];
            }
          }
          catch (const std::regex_error&)
          {
          }
        }
      }
    }
    std::vector<Entry> entries;
    std::string why;
    if (source && (!source->Block || !SplitEntries(source->Value, entries, why)))
    {
      error = "the entry '" + source->Key + "' of the boundaryField of source field '" +
        field.Name + "' is malformed" + (why.empty() ? "" : " (" + why + ")");
      return false;
    }
    const Entry* typeEntry = Find(entries, "type");
    const std::string sourceType = typeEntry ? FirstWord(typeEntry->Value) : "";
    if (IsConstraintType(type) || !source || IsConstraintType(sourceType))
    {
      if (IsConstraintType(type))
      {
        body = "        type            " + type + ";\n";
        return true;
      }
      if (!source && field.Source)
      {
        // warned once per patch by the caller
      }
      body = "        type            zeroGradient;\n";
      return true;
    }
    const std::string internalUniform =
      FirstWord(field.Source->InternalField) == "uniform" ? field.Source->InternalField : "";
    body.clear();
    for (const auto& e : entries)
    {
      if (e.Directive)
      {
        body += "        " + e.Key + " " + e.Value + "\n";
        continue;
      }
      if (e.Block)
      {
        body += "        " + e.Key + "\n        {" + e.Value + "}\n";
        continue;
      }
      std::string value = e.Value;
      if (value.find("$internalField") != std::string::npos && !internalUniform.empty())
      {
        value.replace(value.find("$internalField"), 14, internalUniform);
      }
      const bool internalRef = value.find("$internalField") != std::string::npos;
      if (FirstWord(value) == "nonuniform" || internalRef)
      {
        if (e.Key == "value")
        {
          value = field.UniformValue.empty() ? this->FaceValues(field, p) : field.UniformValue;
        }
        else if (internalRef || !MeanOfList(value, value))
        {
          error = "the entry '" + e.Key + "' of patch '" + source->Key + "' of source field '" +
            field.Name + "' is a list this writer cannot read";
          return false;
        }
      }
      body += "        " + e.Key + " " + value + ";\n";
    }
    return true;
  }

  bool WriteField(const fs::path& dir, const Field& field, std::string& error)
  {
    const vtkIdType nCells = this->Mesh.GetNumberOfCells();
    const char* cls = field.Components == 1 ? "volScalarField" : "volVectorField";
    std::string s = Header(cls, this->StartTime, field.Name, "", this->Binary);
    if (field.Source)
    {
      for (const auto& e : field.Source->TopLevel)
      {
        s += e.Directive ? e.Key + " " + e.Value + "\n"
                         : e.Block ? e.Key + "\n{" + e.Value + "}\n" : e.Key + " " + e.Value + ";\n";
      }
    }
    s += "dimensions      " + (field.Source ? field.Source->Dimensions : "[0 0 0 0 0 0 0]") + ";\n\n";
    std::string tail = "boundaryField\n{\n";
    for (size_t p = 0; p < this->Mesh.Patches.size(); ++p)
    {
      std::string body;
      if (!this->PatchEntry(field, p, body, error))
      {
        return false;
      }
      tail += "    " + this->Mesh.Patches[p].Name + "\n    {\n" + body + "    }\n";
    }
    tail += "}\n";
    return WriteFile(dir / field.Name, [&](std::ostream& out) {
      out << s;
      if (!field.UniformValue.empty())
      {
        out << "internalField   " << field.UniformValue << ";\n\n";
      }
      else
      {
        out << "internalField   nonuniform List<" << (field.Components == 1 ? "scalar" : "vector")
            << "> \n";
        WriteList(out, this->Binary, nCells, [&](std::string& text, vtkIdType c) {
          this->AppendValue(text, field, c);
          if (!this->Binary)
          {
            text += '\n';
          }
        });
        out << ";\n\n";
      }
      out << tail;
    }, error);
  }

  bool WritePolyMesh(const fs::path& dir, std::string& error)
  {
    const vtkARSolverMesh& m = this->Mesh;
    // Every face: the internal ones, then the boundary faces patch by patch.
    std::vector<vtkIdType> owner, neighbour, offsets, connectivity;
    m.GetInternalFaces(owner, neighbour, offsets, connectivity);
    const vtkIdType nInternal = static_cast<vtkIdType>(owner.size());
    for (const auto& p : m.Patches)
    {
      const vtkIdType base = offsets.back();
      for (vtkIdType f = 0; f < p.GetNumberOfFaces(); ++f)
      {
        offsets.push_back(base + p.Offsets[f + 1]);
      }
      connectivity.insert(connectivity.end(), p.Connectivity.begin(), p.Connectivity.end());
      owner.insert(owner.end(), p.Cells.begin(), p.Cells.end());
    }
    const vtkIdType nFaces = static_cast<vtkIdType>(owner.size());
    const bool binary = this->Binary;
    if (binary &&
      static_cast<vtkIdType>(connectivity.size()) > std::numeric_limits<std::int32_t>::max())
    {
      error = "the mesh's faces have " + std::to_string(connectivity.size()) +
        " point ids, more than OpenFOAM's 32-bit labels (label=32) can count";
      return false;
    }
    const std::string note = "nPoints:" + std::to_string(m.GetNumberOfPoints()) +
      "  nCells:" + std::to_string(m.GetNumberOfCells()) + "  nFaces:" + std::to_string(nFaces) +
      "  nInternalFaces:" + std::to_string(nInternal);
    const std::string location = "constant/polyMesh";
    vtkPointSet* pointSet = vtkPointSet::SafeDownCast(m.Volume);
    const bool single =
      pointSet && pointSet->GetPoints() && pointSet->GetPoints()->GetDataType() == VTK_FLOAT;
    auto labels = [binary](const std::vector<vtkIdType>& list) {
      return [binary, &list](std::string& text, vtkIdType i) {
        if (binary)
        {
          AppendRawLabel(text, list[i]);
        }
        else
        {
          AppendLabel(text, list[i]);
          text += '\n';
        }
      };
    };

    bool ok = WriteFile(dir / "points", [&](std::ostream& out) {
      out << Header("vectorField", location, "points", "", binary);
      WriteList(out, binary, m.GetNumberOfPoints(), [&](std::string& text, vtkIdType i) {
        const double* x = &m.Points[3 * i];
        if (binary)
        {
          for (int k = 0; k < 3; ++k)
          {
            AppendRawScalar(text, x[k]);
          }
          return;
        }
        text += '(';
        for (int k = 0; k < 3; ++k)
        {
          if (k)
          {
            text += ' ';
          }
          AppendNumber(text, x[k], single);
        }
        text += ")\n";
      });
    }, error);
    this->Writer->UpdateProgress(0.6);

    // Binary: a faceCompactList (offsets, then the point ids), as OpenFOAM
    // writes binary faces; ASCII: a faceList, n(ids) per face.
    ok = ok && WriteFile(dir / "faces", [&](std::ostream& out) {
      out << Header(binary ? "faceCompactList" : "faceList", location, "faces", "", binary);
      if (binary)
      {
        WriteList(out, true, nFaces + 1, labels(offsets));
        WriteList(out, true, static_cast<vtkIdType>(connectivity.size()), labels(connectivity));
        return;
      }
      WriteList(out, false, nFaces, [&](std::string& text, vtkIdType f) {
        AppendLabel(text, offsets[f + 1] - offsets[f]);
        text += '(';
        for (vtkIdType i = offsets[f]; i < offsets[f + 1]; ++i)
        {
          if (i > offsets[f])
          {
            text += ' ';
          }
          AppendLabel(text, connectivity[i]);
        }
        text += ")\n";
      });
    }, error);
    ok = ok && WriteFile(dir / "owner", [&](std::ostream& out) {
      out << Header("labelList", location, "owner", note, binary);
      WriteList(out, binary, nFaces, labels(owner));
    }, error);
    ok = ok && WriteFile(dir / "neighbour", [&](std::ostream& out) {
      out << Header("labelList", location, "neighbour", note, binary);
      WriteList(out, binary, nInternal, labels(neighbour));
    }, error);
    if (!ok)
    {
      return false;
    }
    this->Writer->UpdateProgress(0.75);

    std::string s = Header("polyBoundaryMesh", location, "boundary");
    s += std::to_string(m.Patches.size()) + "\n(\n";
    vtkIdType start = nInternal;
    for (size_t p = 0; p < m.Patches.size(); ++p)
    {
      s += "    " + m.Patches[p].Name + "\n    {\n";
      s += "        type            " + this->PatchTypes[p] + ";\n";
      for (const auto& e : this->PatchEntries[p])
      {
        if (e.Key == "type")
        {
          continue;
        }
        s += e.Directive ? "        " + e.Key + " " + e.Value + "\n"
          : e.Block      ? "        " + e.Key + "\n        {" + e.Value + "}\n"
                         : "        " + e.Key + " " + e.Value + ";\n";
      }
      if (this->PatchEntries[p].empty() && this->PatchTypes[p] != "patch")
      {
        s += "        inGroups        List<word> 1(" + this->PatchTypes[p] + ");\n";
      }
      s += "        nFaces          " + std::to_string(m.Patches[p].GetNumberOfFaces()) + ";\n";
      s += "        startFace       " + std::to_string(start) + ";\n    }\n";
      start += m.Patches[p].GetNumberOfFaces();
    }
    s += ")\n";
    return Save(dir / "boundary", s, error);
  }

  bool WriteMinimalSystem(const fs::path& dir, std::string& error)
  {
    const std::string loc = "system";
    std::string control = Header("dictionary", loc, "controlDict");
    control += "application     none;\nstartFrom       startTime;\nstartTime       " +
      this->StartTime + ";\nstopAt          endTime;\nendTime         " + this->StartTime +
      ";\ndeltaT          1;\nwriteControl    timeStep;\nwriteInterval   1;\n"
      "purgeWrite      0;\nwriteFormat     ascii;\nwritePrecision  8;\n"
      "writeCompression off;\ntimeFormat      general;\ntimePrecision   8;\n"
      "runTimeModifiable false;\n";
    std::string schemes = Header("dictionary", loc, "fvSchemes");
    schemes += "ddtSchemes\n{\n    default         Euler;\n}\n\ngradSchemes\n{\n    default         "
               "Gauss linear;\n}\n\ndivSchemes\n{\n    default         none;\n}\n\n"
               "laplacianSchemes\n{\n    default         Gauss linear corrected;\n}\n\n"
               "interpolationSchemes\n{\n    default         linear;\n}\n\n"
               "snGradSchemes\n{\n    default         corrected;\n}\n";
    std::string solution = Header("dictionary", loc, "fvSolution");
    solution += "solvers\n{\n}\n\nPIMPLE\n{\n}\n\nSIMPLE\n{\n}\n";
    return Save(dir / "controlDict", control, error) && Save(dir / "fvSchemes", schemes, error) &&
      Save(dir / "fvSolution", solution, error);
  }

  /// system/ and constant/ (but polyMesh) of the source; the source time
  /// directory's subdirectories (includes) but uniform/ and polyMesh/.
  bool CopySource(const fs::path& target, std::string& error)
  {
    const auto options = fs::copy_options::recursive | fs::copy_options::copy_symlinks;
    std::error_code ec;
    fs::copy(this->Source / "system", target / "system", options, ec);
    if (ec)
    {
      error = "copying the SourceCase's system/ failed: " + ec.message();
      return false;
    }
    fs::create_directories(target / "constant", ec);
    for (const auto& d : fs::directory_iterator(this->Source / "constant"))
    {
      if (d.path().filename() == "polyMesh")
      {
        continue;
      }
      fs::copy(d.path(), target / "constant" / d.path().filename(), options, ec);
      if (ec)
      {
        error = "copying '" + d.path().string() + "' failed: " + ec.message();
        return false;
      }
    }
    if (!this->SourceTimeDir.empty())
    {
      for (const auto& d : fs::directory_iterator(this->SourceTimeDir))
      {
        const std::string n = d.path().filename().string();
        if (d.is_directory() && n != "uniform" && n != "polyMesh" && n != "lagrangian")
        {
          fs::copy(d.path(), target / this->StartTime / n, options, ec);
          if (ec)
          {
            error = "copying '" + d.path().string() + "' failed: " + ec.message();
            return false;
          }
        }
      }
    }
    // The copied controlDict is kept; say when it would not start at StartTime.
    std::vector<Entry> control, head;
    std::string ignored;
    if (ReadDictionary(this->Source / "system" / "controlDict", control, head, ignored))
    {
      const Entry* from = Find(control, "startFrom");
      const Entry* time = Find(control, "startTime");
      double a = 0.0, b = 0.0;
      if (from && FirstWord(from->Value) == "startTime" && time &&
        !(IsNumber(FirstWord(time->Value), &a) && IsNumber(this->StartTime, &b) && a == b))
      {
        this->Warnings += "the copied controlDict starts from startTime " + time->Value +
          ", but the fields are in time directory " + this->StartTime +
          " (set StartTime, or the controlDict's startTime)\n";
      }
    }
    return true;
  }

  bool WriteCase(const fs::path& dir, const std::string& marker, std::string& error)
  {
    const fs::path polyMesh = dir / "constant" / "polyMesh";
    fs::create_directories(polyMesh);
    fs::create_directories(dir / this->StartTime);
    if (!this->WritePolyMesh(polyMesh, error))
    {
      return false;
    }
    if (this->Source.empty())
    {
      fs::create_directories(dir / "system");
      if (!this->WriteMinimalSystem(dir / "system", error))
      {
        return false;
      }
    }
    else if (!this->CopySource(dir, error))
    {
      return false;
    }
    for (size_t f = 0; f < this->Fields.size(); ++f)
    {
      if (this->Writer->GetAbortExecute())
      {
        error = "aborted";
        return false;
      }
      if (!this->WriteField(dir / this->StartTime, this->Fields[f], error))
      {
        return false;
      }
      this->Writer->UpdateProgress(0.75 + 0.2 * static_cast<double>(f + 1) / this->Fields.size());
    }
    return Save(dir / marker, "", error) &&
      Save(dir / StampName,
        "OpenFOAM case written by AdaptiveRedistribution's vtkOpenFOAMCaseWriter; the writer "
        "replaces a directory holding this file as a whole.\n",
        error);
  }
};

std::string Quoted(const fs::path& p)
{
  return "'" + p.string() + "'";
}
}

//------------------------------------------------------------------------------
vtkOpenFOAMCaseWriter::vtkOpenFOAMCaseWriter()
{
  this->SetDefaultPatchName("boundary");
  this->SetSourceTime("latest");
  this->SetStartTime("0");
}

vtkOpenFOAMCaseWriter::~vtkOpenFOAMCaseWriter()
{
  this->SetFileName(nullptr);
  this->SetSourceCase(nullptr);
  this->SetSourceTime(nullptr);
  this->SetStartTime(nullptr);
  this->SetDefaultPatchName(nullptr);
}

int vtkOpenFOAMCaseWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  return 1;
}

//------------------------------------------------------------------------------
namespace
{
/// This rank's cells without the ghost copies of other ranks' cells, and
/// without the ghost arrays.
vtkSmartPointer<vtkUnstructuredGrid> OwnedCells(vtkDataSet* piece)
{
  auto owned = vtkSmartPointer<vtkUnstructuredGrid>::New();
  if (auto* grid = vtkUnstructuredGrid::SafeDownCast(piece))
  {
    owned->DeepCopy(grid);
  }
  else if (piece)
  {
    vtkNew<vtkAppendFilter> asGrid; // any other dataset as an unstructured grid
    asGrid->AddInputData(piece);
    asGrid->Update();
    owned->DeepCopy(asGrid->GetOutput());
  }
  owned->RemoveGhostCells();
  owned->GetCellData()->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  owned->GetPointData()->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  return owned;
}

/// The union of the ranks' pieces (each dataset leaf merged with the same
/// leaf of the other ranks, the points the pieces share merged: exact
/// duplicates), on rank 0; nullptr on the other ranks. A multiblock keeps
/// rank 0's structure and block names. Collective.
vtkSmartPointer<vtkDataObject> GatherOnRoot(vtkMultiProcessController* ctrl, vtkDataObject* input)
{
  vtkSmartPointer<vtkDataObject> local;
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
  {
    local.TakeReference(composite->NewInstance());
    local->ShallowCopy(composite);
    auto* out = vtkCompositeDataSet::SafeDownCast(local);
    vtkSmartPointer<vtkCompositeDataIterator> it;
    it.TakeReference(composite->NewIterator());
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      out->SetDataSet(it, OwnedCells(vtkDataSet::SafeDownCast(it->GetCurrentDataObject())));
    }
  }
  else
  {
    local = OwnedCells(vtkDataSet::SafeDownCast(input));
    local->GetFieldData()->ShallowCopy(input ? input->GetFieldData() : nullptr);
  }
  std::vector<vtkSmartPointer<vtkDataObject>> parts;
  ctrl->Gather(local, parts, 0);
  if (ctrl->GetLocalProcessId() != 0)
  {
    return nullptr;
  }
  auto merge = [](const std::vector<vtkDataSet*>& pieces) {
    vtkNew<vtkAppendFilter> append;
    append->MergePointsOn();
    append->SetTolerance(0.0);
    for (vtkDataSet* p : pieces)
    {
      if (p && p->GetNumberOfCells() > 0)
      {
        append->AddInputData(p);
      }
    }
    auto whole = vtkSmartPointer<vtkUnstructuredGrid>::New();
    if (append->GetNumberOfInputConnections(0) > 0)
    {
      append->Update();
      whole->ShallowCopy(append->GetOutput());
    }
    return whole;
  };
  if (vtkCompositeDataSet::SafeDownCast(local))
  {
    auto* out = vtkCompositeDataSet::SafeDownCast(parts[0]);
    vtkSmartPointer<vtkCompositeDataIterator> it;
    it.TakeReference(out->NewIterator());
    it->SkipEmptyNodesOff();
    std::vector<std::pair<unsigned int, vtkSmartPointer<vtkUnstructuredGrid>>> merged;
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      std::vector<vtkDataSet*> pieces;
      for (auto& part : parts)
      {
        auto* other = vtkCompositeDataSet::SafeDownCast(part);
        pieces.push_back(other ? vtkDataSet::SafeDownCast(other->GetDataSet(it)) : nullptr);
      }
      // a leaf another rank fills may be empty on rank 0
      if (std::any_of(pieces.begin(), pieces.end(), [](vtkDataSet* p) { return p != nullptr; }))
      {
        merged.emplace_back(it->GetCurrentFlatIndex(), merge(pieces));
      }
    }
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      for (auto& m : merged)
      {
        if (m.first == it->GetCurrentFlatIndex())
        {
          out->SetDataSet(it, m.second);
        }
      }
    }
    return parts[0];
  }
  std::vector<vtkDataSet*> pieces;
  for (auto& part : parts)
  {
    pieces.push_back(vtkDataSet::SafeDownCast(part));
  }
  vtkSmartPointer<vtkUnstructuredGrid> whole = merge(pieces);
  whole->GetFieldData()->ShallowCopy(parts[0]->GetFieldData());
  return whole;
}
}

//------------------------------------------------------------------------------
vtkTypeBool vtkOpenFOAMCaseWriter::ProcessRequest(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (request->Has(vtkStreamingDemandDrivenPipeline::REQUEST_UPDATE_EXTENT()))
  {
    return this->RequestUpdateExtent(request, inputVector, outputVector);
  }
  return this->Superclass::ProcessRequest(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
int vtkOpenFOAMCaseWriter::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // Under MPI each rank asks for its own piece (without ghost cells): the
  // pieces are gathered and written by rank 0.
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  const int ranks = ctrl ? ctrl->GetNumberOfProcesses() : 1;
  vtkInformation* in = inputVector[0]->GetInformationObject(0);
  if (in && ranks > 1)
  {
    in->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), ctrl->GetLocalProcessId());
    in->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), ranks);
    in->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkOpenFOAMCaseWriter::WriteData()
{
  this->SetErrorCode(vtkErrorCode::NoError);
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  if (ctrl && ctrl->GetNumberOfProcesses() > 1)
  {
    // Distributed (pvbatch, pvserver): the pieces go to rank 0, which writes
    // the case as the serial run would (the same mesh, points merged where
    // the pieces meet, numbered rank by rank).
    vtkSmartPointer<vtkDataObject> whole = GatherOnRoot(ctrl, this->GetInput());
    double code = 0.0;
    if (whole)
    {
      this->WriteCase(whole);
      code = static_cast<double>(this->GetErrorCode());
    }
    ctrl->Broadcast(&code, 1, 0); // every rank reports rank 0's outcome
    this->SetErrorCode(static_cast<unsigned long>(code));
    return;
  }
  this->WriteCase(this->GetInput());
}

//------------------------------------------------------------------------------
void vtkOpenFOAMCaseWriter::WriteCase(vtkDataObject* input)
{
  this->SetErrorCode(vtkErrorCode::NoError);
  const std::string path = this->FileName ? this->FileName : "";
  auto fail = [&](const std::string& why, unsigned long code) {
    vtkErrorMacro("OpenFOAMCaseWriter: " << why << "; nothing is written to '" << path << "'.");
    this->SetErrorCode(code);
  };
  if (path.empty())
  {
    fail("no file name is set (the case's marker file, e.g. case/case.foam)", vtkErrorCode::NoFileNameError);
    return;
  }
  vtkARInputChecks::Properties ranges;
  ranges.InRange("PointMatchingTolerance", this->PointMatchingTolerance, 0.0, 1.0,
    "a fraction of the volume's bounding-box diagonal");
  ranges.OneOf("Format", this->Format, { "ascii", "binary" });
  if (!ranges.Ok())
  {
    const std::string why = ranges.Message();
    fail(why.substr(0, why.size() - 2), vtkErrorCode::UnknownError);
    return;
  }
  CaseJob job;
  job.Writer = this;
  job.Binary = this->Format == BINARY;
  job.StartTime = this->StartTime ? this->StartTime : "";
  job.SourceTime = this->SourceTime ? this->SourceTime : "";
  if (!IsNumber(job.StartTime))
  {
    fail("StartTime '" + job.StartTime + "' is not a number (a time directory name such as 0)",
      vtkErrorCode::UnknownError);
    return;
  }

  // ---- The target: the marker's directory, new, empty or written by us.
  fs::path marker, caseDir;
  std::error_code ec;
  marker = fs::absolute(fs::path(path), ec).lexically_normal();
  caseDir = marker.parent_path();
  if (ec || marker.filename().empty() || caseDir.filename().empty() || caseDir == caseDir.root_path())
  {
    fail("the file name must be <case directory>/<name>.foam, in a case directory (not /)",
      vtkErrorCode::NoFileNameError);
    return;
  }
  const fs::path parent = caseDir.parent_path();
  if (!fs::is_directory(parent, ec))
  {
    fail("the directory " + Quoted(parent) + ", where the case directory " + Quoted(caseDir.filename()) +
        " is made, does not exist",
      vtkErrorCode::CannotOpenFileError);
    return;
  }
  if (fs::exists(caseDir, ec))
  {
    if (!fs::is_directory(caseDir, ec))
    {
      fail(Quoted(caseDir) + " exists and is not a directory", vtkErrorCode::CannotOpenFileError);
      return;
    }
    if (!fs::is_empty(caseDir, ec) && !fs::exists(caseDir / StampName, ec))
    {
      fail("the directory " + Quoted(caseDir) +
          " is not empty and holds no case this writer wrote (it replaces only those): choose a "
          "new or empty directory",
        vtkErrorCode::CannotOpenFileError);
      return;
    }
  }
  if (this->SourceCase && *this->SourceCase)
  {
    job.Source = fs::absolute(fs::path(this->SourceCase), ec).lexically_normal();
    if (!fs::is_directory(job.Source, ec))
    {
      fail("the SourceCase " + Quoted(job.Source) + " is not a directory", vtkErrorCode::FileNotFoundError);
      return;
    }
    if (fs::exists(caseDir, ec) && fs::equivalent(caseDir, job.Source, ec))
    {
      fail("the case directory is the SourceCase itself", vtkErrorCode::CannotOpenFileError);
      return;
    }
  }

  // ---- Mesh, source case, fields.
  const unsigned long code = vtkARSolverMesh::Prepare(this, "OpenFOAMCaseWriter", path, input,
    this->DefaultPatchName, this->PointMatchingTolerance, job.Mesh, /*gathered=*/true);
  if (code != vtkErrorCode::NoError)
  {
    this->SetErrorCode(code);
    return;
  }
  std::string error;
  try
  {
    if (!job.Source.empty() && !job.ReadSource(error))
    {
      fail(error, vtkErrorCode::FileFormatError);
      return;
    }
    job.PatchTypesFromSource();
    if (!job.CollectFields(error))
    {
      fail(error, vtkErrorCode::FileFormatError);
      return;
    }
  }
  catch (const std::exception& e)
  {
    fail(std::string("reading the SourceCase failed: ") + e.what(), vtkErrorCode::FileFormatError);
    return;
  }
  this->UpdateProgress(0.55);

  // ---- Write into a temporary directory next to the target, then rename.
  const std::string pid = std::to_string(static_cast<long>(::getpid()));
  const fs::path temporary = parent / ("." + caseDir.filename().string() + ".writing" + pid);
  const fs::path old = parent / ("." + caseDir.filename().string() + ".replaced" + pid);
  bool ok = false;
  try
  {
    fs::remove_all(temporary);
    if (!fs::create_directory(temporary, ec) || ec)
    {
      error = "cannot create " + Quoted(temporary) + " (is " + Quoted(parent) + " writable?)";
    }
    else
    {
      ok = job.WriteCase(temporary, marker.filename().string(), error);
    }
    if (ok)
    {
      if (fs::exists(caseDir))
      {
        fs::rename(caseDir, old);
        try
        {
          fs::rename(temporary, caseDir);
        }
        catch (...)
        {
          fs::rename(old, caseDir);
          throw;
        }
        fs::remove_all(old, ec);
      }
      else
      {
        fs::rename(temporary, caseDir);
      }
    }
  }
  catch (const std::exception& e)
  {
    error = std::string("writing the case failed: ") + e.what();
    ok = false;
  }
  if (!ok)
  {
    fs::remove_all(temporary, ec);
    fail(error, vtkErrorCode::CannotOpenFileError);
    return;
  }
  if (!job.Warnings.empty())
  {
    vtkWarningMacro("OpenFOAMCaseWriter (" << path << "):\n" << job.Warnings);
  }
  this->UpdateProgress(1.0);
}

void vtkOpenFOAMCaseWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  auto str = [](const char* s) { return s ? s : "(none)"; };
  os << indent << "FileName: " << str(this->FileName) << "\n";
  os << indent << "SourceCase: " << str(this->SourceCase) << "\n";
  os << indent << "SourceTime: " << str(this->SourceTime) << "\n";
  os << indent << "StartTime: " << str(this->StartTime) << "\n";
  os << indent << "DefaultPatchName: " << str(this->DefaultPatchName) << "\n";
  os << indent << "PointMatchingTolerance: " << this->PointMatchingTolerance << "\n";
  os << indent << "Format: " << (this->Format == BINARY ? "binary" : "ascii") << "\n";
}
