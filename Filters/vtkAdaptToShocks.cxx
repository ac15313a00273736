// SPDX-License-Identifier: BSD-3-Clause
#include "vtkAdaptToShocks.h"

#include "vtkARMeshKernels.h"
#include "vtkAppendPolyData.h"
#include "ARSurfaceRemesh.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellTypes.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataObjectTreeIterator.h"
#include "vtkDoubleArray.h"
#include "vtkEmbeddedRemesh.h"
#include "vtkFeatureCluster.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkQuadricFit.h"
#include "vtkShockSensor.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkAdaptToShocks);


//------------------------------------------------------------------------------
vtkAdaptToShocks::vtkAdaptToShocks()
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(2);
}

//------------------------------------------------------------------------------
void vtkAdaptToShocks::SetClusterTemplate(int cluster, int templ)
{
  auto it = this->ClusterTemplates.find(cluster);
  if (it == this->ClusterTemplates.end() || it->second != templ)
  {
    this->ClusterTemplates[cluster] = templ;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkAdaptToShocks::ClearClusterTemplates()
{
  if (!this->ClusterTemplates.empty())
  {
    this->ClusterTemplates.clear();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkAdaptToShocks::FillInputPortInformation(int, vtkInformation* info)
{
  info->Remove(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE());
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkMultiBlockDataSet");
  return 1;
}

//------------------------------------------------------------------------------
int vtkAdaptToShocks::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkDataObject" : "vtkPolyData");
  return 1;
}

//------------------------------------------------------------------------------
int vtkAdaptToShocks::RequestDataObject(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return vtkEmbeddedRemesh::MeshAndSurfaceDataObjects(inputVector, outputVector);
}

//------------------------------------------------------------------------------
int vtkAdaptToShocks::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataObject* input = vtkDataObject::GetData(inputVector[0], 0);
  vtkDataObject* output = vtkDataObject::GetData(outputVector, 0);
  vtkPolyData* surfaces = vtkPolyData::GetData(outputVector, 1);
  surfaces->Initialize();
  auto passThrough = [&](const std::string& message) {
    vtkErrorMacro(<< "AdaptToShocks: " << message << " The input passes through unchanged.");
    output->ShallowCopy(input);
    surfaces->Initialize();
    return 1;
  };
  auto start = std::chrono::steady_clock::now();
  auto lap = [&start]() {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - start).count();
    start = now;
    return s;
  };

  // ---- Properties EmbeddedRemesh or FeatureCluster would clamp: refused here.
  std::ostringstream bad;
  if (this->Mode != 0 && this->Mode != 1)
  {
    bad << "Mode is " << this->Mode << "; it must be 0 (LocalCavity) or 1 (FullDomain). ";
  }
  if (!(this->RemovalFactor > 0.0) || !std::isfinite(this->RemovalFactor) || this->RemovalFactor > 1e3)
  {
    bad << "RemovalFactor is " << this->RemovalFactor << "; it must lie in (0, 1000]. ";
  }
  if (this->MinimumClusterSize < 1)
  {
    bad << "MinimumClusterSize is " << this->MinimumClusterSize << "; it must be at least 1. ";
  }
  if (!(this->MinimumClusterFraction > 0.0 && this->MinimumClusterFraction <= 1.0))
  {
    bad << "MinimumClusterFraction is " << this->MinimumClusterFraction << "; it must lie in (0, 1]. ";
  }
  if (this->MaximumNumberOfSurfaces < 1)
  {
    bad << "MaximumNumberOfSurfaces is " << this->MaximumNumberOfSurfaces << "; it must be at least 1. ";
  }
  for (const auto& ct : this->ClusterTemplates)
  {
    if (ct.second < vtkQuadricFit::PLANE || ct.second > vtkQuadricFit::AUTOMATIC)
    {
      bad << "The template of cluster " << ct.first << " is " << ct.second
          << "; it must be 0 (Plane), 1 (Quadric), 2 (Cone), 3 (Quartic) or 4 (Automatic). ";
    }
  }
  if (!bad.str().empty())
  {
    return passThrough(bad.str());
  }
  vtkUnstructuredGrid* volume = vtkEmbeddedRemesh::VolumeLeaf(input);
  if (!volume || volume->GetNumberOfCells() == 0)
  {
    return passThrough("The input has no volume mesh (an unstructured grid with 3-D cells, or a "
                       "multiblock with an internalMesh).");
  }

  // ---- 1. The shock sensor.
  vtkNew<vtkShockSensor> sensor;
  sensor->SetInputData(volume);
  sensor->SetGamma(this->Gamma);
  sensor->SetGasConstant(this->GasConstant);
  sensor->Update();
  vtkUnstructuredGrid* sensed = sensor->GetOutput();
  if (!sensed->GetPointData()->GetArray("NormalMach"))
  {
    return passThrough("the shock sensor could not run (see its message above).");
  }
  const double secondsSensor = lap();
  this->UpdateProgress(0.2);
  if (this->CheckAbort())
  {
    return 1;
  }

  // ---- 2. The clusters of the Mn = 1 band.
  vtkNew<vtkFeatureCluster> clusters;
  clusters->SetInputConnection(sensor->GetOutputPort());
  clusters->SetSensorRange(this->SensorRange);
  clusters->SetMinimumClusterSize(this->MinimumClusterSize);
  clusters->Update();
  auto* medial = vtkPolyData::SafeDownCast(clusters->GetOutputDataObject(1));
  vtkDataArray* sizes = medial ? medial->GetFieldData()->GetArray("ClusterSizes") : nullptr;
  if (!clusters->GetOutput()->GetPointData()->GetArray("FeatureMask") || !sizes)
  {
    return passThrough("feature clustering could not run (see its message above).");
  }
  if (sizes->GetNumberOfTuples() == 0)
  {
    vtkDataArray* cells = sensed->GetCellData()->GetArray("ShockCells");
    double shockCells = 0.0;
    for (vtkIdType c = 0; cells && c < cells->GetNumberOfTuples(); ++c)
    {
      shockCells += cells->GetComponent(c, 0);
    }
    vtkARMeshKernels::AllReduceSum(&shockCells, 1);
    std::ostringstream msg;
    msg << "No shock found: the shock sensor marks " << shockCells
        << " shock cells, and no cluster of at least MinimumClusterSize (" << this->MinimumClusterSize
        << ") nodes has NormalMach in the sensor range.";
    return passThrough(msg.str());
  }
  // The clusters that get a surface (ids are by decreasing size).
  std::vector<int> chosen;
  const double largest = sizes->GetComponent(0, 0);
  for (vtkIdType k = 0; k < sizes->GetNumberOfTuples() && static_cast<int>(chosen.size()) < this->MaximumNumberOfSurfaces; ++k)
  {
    if (sizes->GetComponent(k, 0) >= this->MinimumClusterFraction * largest)
    {
      chosen.push_back(static_cast<int>(k));
    }
  }
  const double secondsClusters = lap();
  this->UpdateProgress(0.35);
  if (this->CheckAbort())
  {
    return 1;
  }

  // ---- 3. One fitted surface per chosen cluster.
  std::vector<vtkSmartPointer<vtkPolyData>> fitted;
  std::vector<int> fittedCluster;          // the cluster of each fitted surface
  std::vector<std::string> fittedTemplate; // its template's name
  std::ostringstream fitProblems;
  for (const int k : chosen)
  {
    vtkNew<vtkQuadricFit> fit;
    fit->SetInputConnection(clusters->GetOutputPort(1));
    fit->SetDomainData(volume);
    fit->SetClusterId(k);
    const auto named = this->ClusterTemplates.find(k);
    fit->SetTemplate(named == this->ClusterTemplates.end() ? vtkQuadricFit::AUTOMATIC : named->second);
    fit->Update();
    vtkPolyData* surface = fit->GetOutput();
    auto* name = vtkStringArray::SafeDownCast(surface->GetFieldData()->GetAbstractArray("Template"));
    double have = name && surface->GetNumberOfCells() > 0 ? 1.0 : 0.0;
    vtkARMeshKernels::AllReduceMax(&have, 1); // the surface is on rank 0 under MPI
    if (have == 0.0)
    {
      fitProblems << " cluster " << k << " (" << sizes->GetComponent(k, 0) << " nodes)";
      continue;
    }
    auto copy = vtkSmartPointer<vtkPolyData>::New();
    copy->ShallowCopy(surface);
    fitted.push_back(copy);
    fittedCluster.push_back(k);
    fittedTemplate.push_back(name ? name->GetValue(0) : "");
    if (this->CheckAbort())
    {
      return 1;
    }
  }
  if (fitted.empty())
  {
    return passThrough("no surface could be fitted to the shock clusters (" + fitProblems.str() +
      "; see the messages above).");
  }
  if (!fitProblems.str().empty())
  {
    vtkWarningMacro(<< "AdaptToShocks: no surface was fitted to" << fitProblems.str()
                    << "; the other surfaces are used.");
  }
  // A surface that crosses a larger cluster's surface (e.g. a piece of the
  // same shock split off near its foot, or a second shock that meets the
  // first) cannot be embedded with it: it is left out, with a warning.
  {
    auto arrays = [](vtkPolyData* pd, std::vector<double>& p, std::vector<std::int64_t>& t) {
      p.resize(3 * static_cast<std::size_t>(pd->GetNumberOfPoints()));
      for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
      {
        pd->GetPoint(i, &p[3 * i]);
      }
      t.clear();
      vtkIdType npts;
      const vtkIdType* ids;
      vtkCellArray* polys = pd->GetPolys();
      for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
      {
        for (vtkIdType k = 1; k + 1 < npts; ++k)
        {
          t.insert(t.end(), { ids[0], ids[k], ids[k + 1] });
        }
      }
    };
    std::vector<std::vector<double>> pts(fitted.size());
    std::vector<std::vector<std::int64_t>> tris(fitted.size());
    for (std::size_t i = 0; i < fitted.size(); ++i)
    {
      arrays(fitted[i], pts[i], tris[i]);
    }
    std::vector<std::size_t> keptIndex;
    for (std::size_t i = 0; i < fitted.size(); ++i)
    {
      int crossed = -1;
      for (std::size_t j : keptIndex)
      {
        // (every rank decides the same: the surfaces live on rank 0 under MPI)
        double hit = ar::SurfacesIntersect(pts[j], tris[j], pts[i], tris[i]) ? 1.0 : 0.0;
        vtkARMeshKernels::AllReduceMax(&hit, 1);
        if (hit > 0.0)
        {
          crossed = static_cast<int>(j);
          break;
        }
      }
      if (crossed >= 0)
      {
        vtkWarningMacro(<< "AdaptToShocks: the surface of cluster " << fittedCluster[i] << " ("
                        << sizes->GetComponent(fittedCluster[i], 0) << " nodes) crosses the surface of cluster "
                        << fittedCluster[crossed] << " and is left out.");
        continue;
      }
      keptIndex.push_back(i);
    }
    std::vector<vtkSmartPointer<vtkPolyData>> kept;
    for (const std::size_t i : keptIndex)
    {
      kept.push_back(fitted[i]);
      fittedTemplate[kept.size() - 1] = fittedTemplate[i];
    }
    fitted = kept;
    fittedTemplate.resize(kept.size());
  }
  // The kept surfaces, numbered, in one polydata; their templates.
  vtkNew<vtkAppendPolyData> append;
  vtkNew<vtkStringArray> templates;
  templates->SetName("SurfaceTemplates");
  for (std::size_t i = 0; i < fitted.size(); ++i)
  {
    vtkNew<vtkIntArray> id;
    id->SetName("SurfaceId");
    id->SetNumberOfTuples(fitted[i]->GetNumberOfCells());
    id->FillValue(static_cast<int>(i));
    fitted[i]->GetCellData()->AddArray(id);
    append->AddInputData(fitted[i]);
    templates->InsertNextValue(fittedTemplate[i]);
  }
  append->Update();
  const double secondsFit = lap();
  this->UpdateProgress(0.5);

  // ---- 4. The remeshing with every surface embedded.
  vtkNew<vtkEmbeddedRemesh> remesh;
  remesh->SetInputData(input);
  for (const auto& s : fitted)
  {
    remesh->AddSurfaceData(s);
  }
  remesh->SetMode(this->Mode);
  remesh->SetSurfaceEdgeLength(this->SurfaceEdgeLength);
  remesh->SetSurfaceSizeFactor(this->SurfaceSizeFactor);
  remesh->SetLayerType(this->LayerType);
  remesh->SetNumberOfLayers(this->NumberOfLayers);
  remesh->SetRemovalFactor(this->RemovalFactor);
  remesh->SetInterpolateFields(this->InterpolateFields);
  remesh->Update();
  vtkDataObject* adapted = remesh->GetOutputDataObject(0);
  vtkUnstructuredGrid* adaptedVolume = vtkEmbeddedRemesh::VolumeLeaf(adapted);
  if (!adaptedVolume || !adaptedVolume->GetCellData()->GetArray("Region"))
  {
    return passThrough("the remeshing failed (see EmbeddedRemesh's message above).");
  }
  const double secondsRemesh = lap();

  output->ShallowCopy(adapted);
  surfaces->ShallowCopy(append->GetOutput());
  vtkUnstructuredGrid* outVolume = vtkEmbeddedRemesh::VolumeLeaf(output);
  vtkFieldData* fd = outVolume->GetFieldData();
  const double count = static_cast<double>(fitted.size());
  fd->AddArray(vtkARMeshKernels::FieldArray("NumberOfSurfaces", &count, 1));
  fd->AddArray(templates);
  fd->AddArray(vtkARMeshKernels::FieldArray("SecondsSensor", &secondsSensor, 1));
  fd->AddArray(vtkARMeshKernels::FieldArray("SecondsClusters", &secondsClusters, 1));
  fd->AddArray(vtkARMeshKernels::FieldArray("SecondsFit", &secondsFit, 1));
  fd->AddArray(vtkARMeshKernels::FieldArray("SecondsRemesh", &secondsRemesh, 1));
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkAdaptToShocks::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Gamma: " << this->Gamma << "\n";
  os << indent << "GasConstant: " << this->GasConstant << "\n";
  os << indent << "SensorRange: " << this->SensorRange[0] << " " << this->SensorRange[1] << "\n";
  os << indent << "MinimumClusterSize: " << this->MinimumClusterSize << "\n";
  os << indent << "MinimumClusterFraction: " << this->MinimumClusterFraction << "\n";
  os << indent << "MaximumNumberOfSurfaces: " << this->MaximumNumberOfSurfaces << "\n";
  for (const auto& ct : this->ClusterTemplates)
  {
    os << indent << "ClusterTemplate " << ct.first << ": " << ct.second << "\n";
  }
  os << indent << "Mode: " << this->Mode << "\n";
  os << indent << "SurfaceEdgeLength: " << this->SurfaceEdgeLength << "\n";
  os << indent << "SurfaceSizeFactor: " << this->SurfaceSizeFactor << "\n";
  os << indent << "LayerType: " << this->LayerType << "\n";
  os << indent << "NumberOfLayers: " << this->NumberOfLayers << "\n";
  os << indent << "RemovalFactor: " << this->RemovalFactor << "\n";
  os << indent << "InterpolateFields: " << this->InterpolateFields << "\n";
}
