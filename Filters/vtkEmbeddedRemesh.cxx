// SPDX-License-Identifier: BSD-3-Clause
#include "vtkEmbeddedRemesh.h"

#include "ARCavity.h"
#include "ARSurfaceRemesh.h"
#include "ARTetGeometry.h"
#include "vtkARMeshKernels.h"

#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkCellTypes.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataObjectTreeIterator.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkGenericCell.h"
#include "vtkGeometryFilter.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStaticCellLocator.h"
#include "vtkStaticCleanPolyData.h"
#include "vtkStaticPointLocator.h"
#include "vtkTriangleFilter.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkEmbeddedRemesh);

//------------------------------------------------------------------------------
vtkEmbeddedRemesh::vtkEmbeddedRemesh()
{
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(2);
}

//------------------------------------------------------------------------------
int vtkEmbeddedRemesh::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Remove(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE());
    info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
    info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkMultiBlockDataSet");
    return 1;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  info->Set(vtkAlgorithm::INPUT_IS_REPEATABLE(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkEmbeddedRemesh::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkDataObject" : "vtkPolyData");
  return 1;
}

//------------------------------------------------------------------------------
int vtkEmbeddedRemesh::RequestDataObject(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataObject* input = vtkDataObject::GetData(inputVector[0], 0);
  if (!input)
  {
    return 0;
  }
  vtkInformation* info = outputVector->GetInformationObject(0);
  vtkDataObject* output = info->Get(vtkDataObject::DATA_OBJECT());
  const bool composite = vtkMultiBlockDataSet::SafeDownCast(input) != nullptr;
  if (!output || (composite ? !vtkMultiBlockDataSet::SafeDownCast(output) : !vtkUnstructuredGrid::SafeDownCast(output)))
  {
    vtkSmartPointer<vtkDataObject> fresh;
    if (composite)
    {
      fresh = vtkSmartPointer<vtkMultiBlockDataSet>::New();
    }
    else
    {
      fresh = vtkSmartPointer<vtkUnstructuredGrid>::New();
    }
    info->Set(vtkDataObject::DATA_OBJECT(), fresh);
  }
  vtkInformation* info1 = outputVector->GetInformationObject(1);
  if (!vtkPolyData::SafeDownCast(info1->Get(vtkDataObject::DATA_OBJECT())))
  {
    info1->Set(vtkDataObject::DATA_OBJECT(), vtkSmartPointer<vtkPolyData>::New());
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkEmbeddedRemesh::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataObject* inputObject = vtkDataObject::GetData(inputVector[0], 0);
  vtkPolyData* embedded = vtkPolyData::GetData(outputVector, 1);
  embedded->Initialize();
  std::vector<vtkDataSet*> surfaces;
  for (int k = 0; k < inputVector[1]->GetNumberOfInformationObjects(); ++k)
  {
    surfaces.push_back(vtkDataSet::GetData(inputVector[1], k));
  }
  if (auto* grid = vtkUnstructuredGrid::SafeDownCast(inputObject))
  {
    return this->RemeshVolume(grid, surfaces, vtkUnstructuredGrid::GetData(outputVector, 0), embedded);
  }
  // A multiblock (ParaView's OpenFOAM reader): the volume leaf ("internalMesh",
  // else the first unstructured grid with 3-D cells) is remeshed; the patch
  // leaves pass through, as the boundary does not change.
  auto* input = vtkMultiBlockDataSet::SafeDownCast(inputObject);
  auto* output = vtkMultiBlockDataSet::GetData(outputVector, 0);
  output->CopyStructure(input);
  vtkUnstructuredGrid* volume = nullptr;
  vtkSmartPointer<vtkDataObjectTreeIterator> it;
  it.TakeReference(input->NewTreeIterator());
  for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
  {
    auto* grid = vtkUnstructuredGrid::SafeDownCast(it->GetCurrentDataObject());
    const char* name = it->GetCurrentMetaData()->Get(vtkCompositeDataSet::NAME());
    const bool isInternal = name && std::string(name) == "internalMesh";
    bool solid = false;
    for (vtkIdType c = 0; grid && c < grid->GetNumberOfCells() && !solid; ++c)
    {
      solid = vtkCellTypes::GetDimension(grid->GetCellType(c)) == 3;
    }
    if (grid && solid && (isInternal || !volume))
    {
      volume = grid;
      if (isInternal)
      {
        break;
      }
    }
  }
  vtkNew<vtkUnstructuredGrid> remeshed;
  if (!volume)
  {
    vtkErrorMacro(<< "The multiblock input has no block with 3-D cells (e.g. internalMesh). The "
                     "input passes through unchanged.");
    output->ShallowCopy(input);
    return 1;
  }
  this->RemeshVolume(volume, surfaces, remeshed, embedded);
  for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
  {
    vtkDataObject* leaf = it->GetCurrentDataObject();
    if (leaf == volume)
    {
      output->SetDataSet(it, remeshed);
    }
    else if (leaf)
    {
      vtkSmartPointer<vtkDataObject> copy;
      copy.TakeReference(leaf->NewInstance());
      copy->ShallowCopy(leaf);
      output->SetDataSet(it, copy);
    }
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkEmbeddedRemesh::RemeshVolume(vtkUnstructuredGrid* input,
  const std::vector<vtkDataSet*>& surfaces, vtkUnstructuredGrid* output, vtkPolyData* embedded)
{
  auto passThrough = [&](const std::string& message) {
    vtkErrorMacro(<< message << " The input passes through unchanged.");
    output->ShallowCopy(input);
    return 1;
  };
  if (vtkARMeshKernels::NumberOfRanks() > 1)
  {
    return passThrough("EmbeddedRemesh does not run on distributed data yet (gather the mesh "
                       "to one rank first, e.g. with Merge Blocks on a single-rank session).");
  }
  if (!input || input->GetNumberOfCells() == 0)
  {
    return passThrough("The volume mesh is empty.");
  }

  // ---- The feature surfaces, merged and triangulated.
  vtkNew<vtkAppendPolyData> append;
  for (vtkDataSet* ds : surfaces)
  {
    if (!ds || ds->GetNumberOfCells() == 0)
    {
      continue;
    }
    vtkNew<vtkGeometryFilter> geometry;
    geometry->SetInputData(ds);
    vtkNew<vtkTriangleFilter> triangles;
    triangles->SetInputConnection(geometry->GetOutputPort());
    triangles->PassVertsOff();
    triangles->PassLinesOff();
    triangles->Update();
    vtkNew<vtkPolyData> bare; // geometry only: S's arrays are not wanted
    bare->SetPoints(triangles->GetOutput()->GetPoints());
    bare->SetPolys(triangles->GetOutput()->GetPolys());
    append->AddInputData(bare);
  }
  if (append->GetNumberOfInputConnections(0) == 0)
  {
    return passThrough("The feature surface is empty (no Surfaces connected, or none has cells).");
  }
  vtkNew<vtkStaticCleanPolyData> clean;
  clean->SetInputConnection(append->GetOutputPort());
  clean->SetTolerance(0.0);
  clean->Update();
  vtkPolyData* surface = clean->GetOutput();
  std::vector<double> sPoints(3 * surface->GetNumberOfPoints());
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
  {
    surface->GetPoint(i, &sPoints[3 * i]);
  }
  std::vector<std::int64_t> sTris;
  {
    vtkIdType npts;
    const vtkIdType* ids;
    vtkCellArray* polys = surface->GetPolys();
    for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
    {
      if (npts == 3)
      {
        sTris.insert(sTris.end(), { ids[0], ids[1], ids[2] });
      }
    }
  }
  if (sTris.empty())
  {
    return passThrough("The feature surface has no triangles.");
  }

  // ---- V: its tetrahedra; other 3-D cells are kept and lock their nodes.
  const vtkIdType nPoints = input->GetNumberOfPoints();
  ar::TetMesh tets;
  tets.Points.resize(3 * nPoints);
  for (vtkIdType i = 0; i < nPoints; ++i)
  {
    input->GetPoint(i, &tets.Points[3 * i]);
  }
  ar::CavityOptions options;
  options.LockedNodes.assign(nPoints, 0);
  std::vector<vtkIdType> tetCell, otherCell;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
  {
    const int type = input->GetCellType(c);
    input->GetCellPoints(c, ids);
    if (type == VTK_TETRA)
    {
      for (vtkIdType k = 0; k < 4; ++k)
      {
        tets.Tetrahedra.push_back(ids->GetId(k));
      }
      tetCell.push_back(c);
    }
    else if (type == VTK_HEXAHEDRON || type == VTK_WEDGE || type == VTK_PYRAMID ||
      type == VTK_VOXEL || type == VTK_POLYHEDRON || type == VTK_TRIANGLE || type == VTK_QUAD ||
      type == VTK_POLYGON)
    {
      // Kept as they are: other 3-D cells, and boundary-patch faces (2-D
      // cells with a PatchId, as the solver writers take them).
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
      {
        options.LockedNodes[ids->GetId(k)] = 1;
      }
      otherCell.push_back(c);
    }
    else
    {
      std::ostringstream msg;
      msg << "Cell " << c << " has type " << type
          << "; EmbeddedRemesh takes linear 3-D cells (tetrahedra are remeshed; hexahedra, "
             "wedges, pyramids and polyhedra are kept) and triangles, quads or polygons as "
             "boundary-patch faces (kept).";
      return passThrough(msg.str());
    }
  }
  if (tetCell.empty())
  {
    return passThrough("The volume mesh has no tetrahedra to remesh.");
  }
  this->UpdateProgress(0.1);

  // ---- S remeshed at the edge length.
  double edge = this->SurfaceEdgeLength;
  if (edge <= 0.0)
  {
    std::vector<double> lv(nPoints, 0.0);
    for (std::size_t t = 0; t < tets.NumberOfTetrahedra(); ++t)
    {
      const std::int64_t* v = &tets.Tetrahedra[4 * t];
      for (int a = 0; a < 4; ++a)
      {
        for (int b = a + 1; b < 4; ++b)
        {
          const double* p = &tets.Points[3 * v[a]];
          const double* q = &tets.Points[3 * v[b]];
          const double l = std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
            (p[2] - q[2]) * (p[2] - q[2]));
          lv[v[a]] = std::max(lv[v[a]], l);
          lv[v[b]] = std::max(lv[v[b]], l);
        }
      }
    }
    vtkNew<vtkStaticPointLocator> locator;
    locator->SetDataSet(input);
    locator->BuildLocator();
    std::vector<double> near;
    for (std::size_t i = 0; i < sPoints.size() / 3; ++i)
    {
      const vtkIdType j = locator->FindClosestPoint(&sPoints[3 * i]);
      if (j >= 0 && lv[j] > 0.0)
      {
        near.push_back(lv[j]);
      }
    }
    if (near.empty())
    {
      return passThrough("Could not find the mesh size near the feature surface; set SurfaceEdgeLength.");
    }
    std::nth_element(near.begin(), near.begin() + near.size() / 2, near.end());
    edge = near[near.size() / 2];
  }
  std::vector<double> rPoints;
  std::vector<std::int64_t> rTris;
  std::string error;
  if (!ar::RemeshSurfaceIsotropic(sPoints, sTris, edge, rPoints, rTris, error))
  {
    vtkWarningMacro(<< "The feature surface is used as it is (not remeshed): " << error);
    rPoints = sPoints;
    rTris = sTris;
  }
  this->UpdateProgress(0.3);

  // ---- The cavity and its refill.
  options.RemovalFactor = this->RemovalFactor;
  options.VisibilityTest = this->VisibilityTest;
  options.BoundaryMargin = this->BoundaryMargin;
  options.FullDomain = this->Mode == FULL_DOMAIN;
  options.Quality.MaxRadiusEdgeRatio = this->MaxRadiusEdgeRatio;
  options.Quality.MinDihedralAngle = this->MinDihedralAngle;
  ar::CavityRemesh result;
  if (!ar::RemeshLocalCavity(tets, rPoints.data(), rPoints.size() / 3, rTris.data(), rTris.size() / 3,
        options, result, error))
  {
    return passThrough("EmbeddedRemesh: " + error);
  }
  this->UpdateProgress(0.8);

  // ---- Output mesh: new tetrahedra and kept cells, in the output's point ids.
  const auto nOut = static_cast<vtkIdType>(result.SourcePoint.size());
  std::vector<vtkIdType> outOfInput(nPoints, -1);
  for (vtkIdType i = 0; i < nOut; ++i)
  {
    if (result.SourcePoint[i] >= 0)
    {
      outOfInput[result.SourcePoint[i]] = i;
    }
  }
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(nOut);
  for (vtkIdType i = 0; i < nOut; ++i)
  {
    points->SetPoint(i, &result.Mesh.Points[3 * i]);
  }
  output->Initialize();
  output->GetFieldData()->ShallowCopy(input->GetFieldData());
  output->SetPoints(points);
  const auto nTets = static_cast<vtkIdType>(result.SourceCell.size());
  output->Allocate(nTets + static_cast<vtkIdType>(otherCell.size()));
  std::vector<vtkIdType> sourceCell; // input cell of each output cell, -1 new
  vtkNew<vtkIntArray> region;
  region->SetName("Region");
  vtkNew<vtkDoubleArray> minAngle;
  minAngle->SetName("MinDihedralAngle");
  double newMin = 180.0, newSum = 0.0;
  vtkIdType newCount = 0;
  for (vtkIdType t = 0; t < nTets; ++t)
  {
    const std::int64_t* v = &result.Mesh.Tetrahedra[4 * t];
    const vtkIdType pts[4] = { v[0], v[1], v[2], v[3] };
    output->InsertNextCell(VTK_TETRA, 4, pts);
    const std::int64_t src = result.SourceCell[t];
    sourceCell.push_back(src >= 0 ? tetCell[src] : -1);
    region->InsertNextValue(src >= 0 ? 0 : 1);
    double a[6];
    ar::TetDihedralAngles(&result.Mesh.Points[3 * v[0]], &result.Mesh.Points[3 * v[1]],
      &result.Mesh.Points[3 * v[2]], &result.Mesh.Points[3 * v[3]], a);
    const double m = *std::min_element(a, a + 6);
    minAngle->InsertNextValue(m);
    if (src < 0)
    {
      newMin = std::min(newMin, m);
      newSum += m;
      ++newCount;
    }
  }
  for (vtkIdType c : otherCell)
  {
    input->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      ids->SetId(k, outOfInput[ids->GetId(k)]);
    }
    if (input->GetCellType(c) == VTK_POLYHEDRON)
    {
      vtkNew<vtkIdList> faces;
      input->GetFaceStream(c, faces);
      // The face stream holds point ids after each face's count: map them.
      vtkIdType pos = 1;
      for (vtkIdType f = 0; f < faces->GetId(0); ++f)
      {
        const vtkIdType n = faces->GetId(pos++);
        for (vtkIdType k = 0; k < n; ++k, ++pos)
        {
          faces->SetId(pos, outOfInput[faces->GetId(pos)]);
        }
      }
      output->InsertNextCell(VTK_POLYHEDRON, faces);
    }
    else
    {
      output->InsertNextCell(input->GetCellType(c), ids);
    }
    sourceCell.push_back(c);
    region->InsertNextValue(0);
    minAngle->InsertNextValue(-1.0);
  }

  // ---- Fields: kept points and cells copy theirs; new ones interpolate.
  if (this->InterpolateFields)
  {
    vtkPointData* inPD = input->GetPointData();
    vtkPointData* outPD = output->GetPointData();
    vtkCellData* inCD = input->GetCellData();
    vtkCellData* outCD = output->GetCellData();
    outPD->InterpolateAllocate(inPD, nOut);
    outCD->CopyAllocate(inCD, static_cast<vtkIdType>(sourceCell.size()));
    vtkNew<vtkStaticCellLocator> cells;
    cells->SetDataSet(input);
    cells->BuildLocator();
    vtkNew<vtkGenericCell> cell;
    std::vector<double> weights(VTK_CELL_SIZE);
    double pcoords[3];
    int subId;
    vtkNew<vtkStaticPointLocator> nearest;
    nearest->SetDataSet(input);
    nearest->BuildLocator();
    const double tol2 = 1e-12 * input->GetLength2();
    for (vtkIdType i = 0; i < nOut; ++i)
    {
      if (result.SourcePoint[i] >= 0)
      {
        outPD->CopyData(inPD, result.SourcePoint[i], i);
        continue;
      }
      double x[3];
      points->GetPoint(i, x);
      const vtkIdType c = cells->FindCell(x, tol2, cell, subId, pcoords, weights.data());
      if (c >= 0)
      {
        outPD->InterpolatePoint(inPD, i, cell->PointIds, weights.data());
      }
      else
      {
        outPD->CopyData(inPD, nearest->FindClosestPoint(x), i);
      }
    }
    for (std::size_t k = 0; k < sourceCell.size(); ++k)
    {
      vtkIdType src = sourceCell[k];
      if (src < 0)
      {
        double centre[3] = { 0.0, 0.0, 0.0 };
        const std::int64_t* v = &result.Mesh.Tetrahedra[4 * k];
        for (int j = 0; j < 4; ++j)
        {
          for (int d = 0; d < 3; ++d)
          {
            centre[d] += 0.25 * result.Mesh.Points[3 * v[j] + d];
          }
        }
        src = cells->FindCell(centre, tol2, cell, subId, pcoords, weights.data());
        if (src < 0)
        {
          double closest[3], dist2;
          cells->FindClosestPoint(centre, closest, cell, src, subId, dist2);
        }
      }
      outCD->CopyData(inCD, src, static_cast<vtkIdType>(k));
    }
  }
  output->GetCellData()->AddArray(region);
  output->GetCellData()->AddArray(minAngle);

  // ---- Field data and the embedded surface.
  const ar::TetMeshStatistics before = ar::ComputeStatistics(tets);
  const ar::TetMeshStatistics after = ar::ComputeStatistics(result.Mesh);
  auto field = [&](const char* name, double value) {
    output->GetFieldData()->AddArray(vtkARMeshKernels::FieldArray(name, &value, 1));
  };
  field("KeptCells", static_cast<double>(sourceCell.size() - newCount));
  field("NewCells", static_cast<double>(newCount));
  field("RemovedNodes", static_cast<double>(result.RemovedNodes));
  field("SurfaceTriangles", static_cast<double>(result.Surface.size() / 3));
  field("SurfaceEdgeLength", edge);
  field("MinDihedralAngleNew", newCount ? newMin : 0.0);
  field("MeanDihedralAngleNew", newCount ? newSum / newCount : 0.0);
  field("RelativeVolumeChange",
    before.TotalVolume > 0.0 ? (after.TotalVolume - before.TotalVolume) / before.TotalVolume : 0.0);
  vtkNew<vtkCellArray> faces;
  for (std::size_t f = 0; f < result.Surface.size(); f += 3)
  {
    const vtkIdType tri[3] = { result.Surface[f], result.Surface[f + 1], result.Surface[f + 2] };
    faces->InsertNextCell(3, tri);
  }
  embedded->SetPoints(points);
  embedded->SetPolys(faces);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkEmbeddedRemesh::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Mode: " << this->Mode << "\n";
  os << indent << "SurfaceEdgeLength: " << this->SurfaceEdgeLength << "\n";
  os << indent << "RemovalFactor: " << this->RemovalFactor << "\n";
  os << indent << "VisibilityTest: " << this->VisibilityTest << "\n";
  os << indent << "BoundaryMargin: " << this->BoundaryMargin << "\n";
  os << indent << "MaxRadiusEdgeRatio: " << this->MaxRadiusEdgeRatio << "\n";
  os << indent << "MinDihedralAngle: " << this->MinDihedralAngle << "\n";
  os << indent << "InterpolateFields: " << this->InterpolateFields << "\n";
}
